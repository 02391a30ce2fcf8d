//! End-to-end tests of box-split grammars: the real binary on the shipped
//! `examples/boxsplit` grammars and the real terrain in `examples/terrain`.

mod common;

use common::{genform, root, s};
use genform_core::BlockKind;
use genform_export::minecraft::{RegionFile, read_litematic, read_schem, read_terrain};
use glam::IVec3;
use std::path::PathBuf;

fn bsg(name: &str) -> PathBuf {
    root().join("examples/boxsplit").join(format!("{name}.bsg"))
}

fn prismarine() -> PathBuf {
    root().join("examples/terrain/prismarine-1.21.1/r.0.0.mca")
}

#[test]
fn castle_schematics_are_deterministic_and_read_back() {
    let tmp = tempfile::tempdir().unwrap();
    let castle = bsg("castle");
    for out in ["a.schem", "b.schem", "c.litematic"] {
        genform(tmp.path(), &["sample", s(&castle), "--box", "0,0,0,47,23,47", "--seed", "4", "--out", out]).ok();
    }
    let a = std::fs::read(tmp.path().join("a.schem")).unwrap();
    assert_eq!(a, std::fs::read(tmp.path().join("b.schem")).unwrap(), "same seed, same bytes");
    let schem = read_schem(&a).unwrap();
    assert_eq!(schem.size, glam::UVec3::new(48, 24, 48));
    let lit = read_litematic(&std::fs::read(tmp.path().join("c.litematic")).unwrap()).unwrap();
    assert_eq!(lit.size, schem.size);
    let solid = |g: &genform_core::BlockGrid| {
        g.cells.iter().filter(|&&c| c != u32::MAX && g.palette[c as usize].kind() == BlockKind::Solid).count()
    };
    assert!(solid(&schem) > 5000, "a castle has walls");
    assert_eq!(solid(&schem), solid(&lit));
    let v3 =
        ["sample", s(&castle), "--box", "0,0,0,47,23,47", "--seed", "4", "--schem-version", "3", "--out", "d.schem"];
    genform(tmp.path(), &v3).ok();
    let d = std::fs::read(tmp.path().join("d.schem")).unwrap();
    assert_ne!(d, a, "version 3 is laid out differently");
    assert_eq!(read_schem(&d).unwrap().cells.len(), schem.cells.len());
}

#[test]
fn bridge_on_real_terrain_goes_into_a_copy_of_the_region() {
    let tmp = tempfile::tempdir().unwrap();
    let world = prismarine();
    let bridge = bsg("bridge");
    let args = ["sample", s(&bridge), "--world", s(&world), "--box", "6,50,3,62,65,5", "--trace", "t.json"];
    genform(tmp.path(), &[&args[..], &["--out", "r.0.0.mca"]].concat()).ok();
    let original = RegionFile { x: 0, z: 0, bytes: std::fs::read(&world).unwrap() };
    let copy = RegionFile { x: 0, z: 0, bytes: std::fs::read(tmp.path().join("r.0.0.mca")).unwrap() };
    let (min, max) = (IVec3::new(6, 50, 3), IVec3::new(63, 66, 6));
    let before = read_terrain(std::slice::from_ref(&original), min, max).unwrap();
    let after = read_terrain(std::slice::from_ref(&copy), min, max).unwrap();
    // The deck is on the top layers wherever the bank does not rise into it.
    let planks = (6..63)
        .filter(|&x| {
            after.get(IVec3::new(x, 64, 4)).is_some_and(|b| b.id().ends_with("planks") || b.id().contains("spruce"))
        })
        .count();
    assert!(planks > 40, "deck blocks: {planks}");
    // No solid terrain block was replaced, and every placed support block
    // stands on solid terrain or on another support block.
    let mut supports = 0;
    for x in 6..63 {
        for z in 3..6 {
            for y in 51..64 {
                let p = IVec3::new(x, y, z);
                let (b, a) = (before.get(p).unwrap(), after.get(p).unwrap());
                if b.kind() == BlockKind::Solid {
                    assert_eq!(a, b, "terrain at {p} was replaced");
                } else if a != b {
                    supports += 1;
                    let q = p - IVec3::Y;
                    let (qb, qa) = (before.get(q).unwrap(), after.get(q).unwrap());
                    assert!(qb.kind() == BlockKind::Solid || qa != qb, "the support block at {p} floats");
                }
            }
        }
    }
    assert!(supports > 20, "the piers reach down through the water: {supports} blocks");
    let trace: serde_json::Value = serde_json::from_slice(&std::fs::read(tmp.path().join("t.json")).unwrap()).unwrap();
    assert!(trace["events"].as_array().is_some_and(|e| e.len() > 100), "the trace records the choices");
    // Chunks outside the box are untouched.
    let far = (IVec3::new(48, 60, 48), IVec3::new(64, 70, 64));
    assert_eq!(read_terrain(&[original], far.0, far.1).unwrap(), read_terrain(&[copy], far.0, far.1).unwrap());
}

#[test]
fn box_split_errors_are_clear() {
    let tmp = tempfile::tempdir().unwrap();
    let castle = bsg("castle");
    std::fs::write(tmp.path().join("nobox.bsg"), "A { fill stone }\n").unwrap();
    let err = genform(tmp.path(), &["sample", "nobox.bsg", "--out", "c.schem"]).fails().stderr();
    assert!(err.contains("--box") && err.contains("box x0, y0, z0, x1, y1, z1;"), "{err}");
    let err = genform(tmp.path(), &["sample", s(&castle), "--box", "0,0,0,9,9,9", "--out", "c.mca"]).fails().stderr();
    assert!(err.contains("needs --world"), "{err}");
    let world = prismarine();
    let err = genform(
        tmp.path(),
        &["sample", s(&castle), "--world", s(&world), "--box", "0,60,0,9,69,9", "--out", s(&world)],
    )
    .fails()
    .stderr();
    assert!(err.contains("is the world") && err.contains("an input of this command"), "{err}");
    for corners in ["0,0,0,2147483647,3,3", "-2147483648,0,0,3,3,3", "0,0,0,30000001,3,3"] {
        let err = genform(tmp.path(), &["sample", s(&castle), "--box", corners]).fails().stderr();
        assert!(err.contains("past the edge of a Minecraft world"), "{corners}: {err}");
    }
    std::fs::write(tmp.path().join("bad.bsg"), "axiom A;\nA { when X > 100 { fill stone } }\n").unwrap();
    let run = genform(tmp.path(), &["sample", "bad.bsg", "--box", "0,0,0,3,3,3", "--trace", "t.json"]).fails();
    assert!(run.stderr().contains("bad.bsg: the derivation failed") && run.stderr().contains('A'), "{}", run.stderr());
    assert!(tmp.path().join("t.json").exists(), "a failed derivation still writes its trace");
    std::fs::write(tmp.path().join("bad.bsg"), "axiom A;\nA { split q [1] { B } }\n").unwrap();
    let err = genform(tmp.path(), &["sample", "bad.bsg", "--box", "0,0,0,3,3,3"]).fails().stderr();
    assert!(err.contains("bad.bsg:2:"), "{err}");
}

#[test]
fn a_flat_box_is_drawn_as_tiles() {
    let tmp = tempfile::tempdir().unwrap();
    let mosaic = bsg("mosaic");
    genform(tmp.path(), &["sample", s(&mosaic), "--box", "0,0,0,47,0,47", "--seed", "1", "--out", "m.png"]).ok();
    let png = std::fs::read(tmp.path().join("m.png")).unwrap();
    let decoder = png::Decoder::new(std::io::Cursor::new(png));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    let (w, h) = (info.width as usize, info.height as usize);
    // The border is dark oak planks all round, in flat tiles (no shading):
    // the same colour at two different places of it.
    let px = |x: usize, y: usize| buf[(y * w + x) * 3..(y * w + x) * 3 + 3].to_vec();
    let tile = (w / 48).min(h / 48);
    let (ox, oy) = ((w - 48 * tile) / 2, (h - 48 * tile) / 2);
    assert_eq!(px(ox + tile / 2, oy + tile / 2), px(ox + 47 * tile + tile / 2, oy + 20 * tile));
    assert_ne!(px(ox + tile / 2, oy + tile / 2), px(ox + 24 * tile, oy + 24 * tile));
}

#[test]
fn a_site_refuses_a_box_in_the_ground_and_warns_of_a_foundation_that_hangs() {
    let tmp = tempfile::tempdir().unwrap();
    let house = bsg("house");
    let world = prismarine();
    // The house's own box (y 0..12) lies deep in the ground of a world.
    let err = genform(tmp.path(), &["sample", s(&house), "--world", s(&world), "--out", "h.schem"]).fails().stderr();
    assert!(err.contains("no floor") && err.contains("give a box whose top is above the ground"), "{err}");
    // A box whose bottom is above the river's bed in the west of the map:
    // the foundation reaches the box's bottom in water and says so.
    let run = genform(
        tmp.path(),
        &["sample", s(&house), "--world", s(&world), "--box", "14,58,14,29,80,25", "--out", "h.schem"],
    )
    .ok();
    let said = run.stderr();
    assert!(said.contains("site: floor at y 63"), "{said}");
    assert!(said.contains("foundation stands on nothing below the box") && said.contains("y 57 or below"), "{said}");
}
