//! Expression: runs a finished genome and writes a [`Scene`].

use crate::grammar::ShapeGrammar;
use crate::interp::{self, Mode, Stop};
use crate::program::SlotCode;
use crate::scratch::with_scratch;
use genform_core::genome::{GenePos, Link};
use genform_core::scene::Polygon;
use genform_core::{ExpressError, Genome, Instance, LimitKind, Limits, Mesh, Primitive, Scene};
use glam::Affine3A;
use std::sync::Arc;

/// Not yet added to the scene (in [`ExpressMode::tags`] and `meshes`).
const UNSEEN: u32 = u32::MAX;

/// Express mode: links are read from a finished genome; geometry goes to a Scene.
pub(crate) struct ExpressMode<'a> {
    pub genome: &'a Genome,
    pub scene: &'a mut Scene,
    /// Grammar tag → scene tag. Tags are interned on first use, so the
    /// scene lists only the tags it uses, in order of first emission.
    pub tags: Vec<u32>,
    /// Grammar mesh → scene mesh, likewise.
    pub meshes: Vec<u32>,
}

impl Mode for ExpressMode<'_> {
    fn genome(&self) -> &Genome {
        self.genome
    }

    #[inline]
    fn touch(&mut self, gene: GenePos, link: usize, _: &SlotCode, _: usize) -> Result<Option<GenePos>, Stop> {
        Ok(match self.genome.gene(gene).link(link) {
            Link::Child(c) => Some(c),
            _ => None,
        })
    }

    #[inline]
    fn emit(&mut self, g: &ShapeGrammar, transform: Affine3A, prim: Primitive, tag: u32) {
        let t = tag as usize;
        if self.tags[t] == UNSEEN {
            self.intern(g, t);
        }
        let primitive = match prim {
            Primitive::Mesh(m) => {
                let m = m as usize;
                if self.meshes[m] == UNSEEN {
                    self.meshes[m] = self.scene.mesh(&g.meshes[m]);
                }
                Primitive::Mesh(self.meshes[m])
            }
            p => p,
        };
        self.scene.instances.push(Instance { transform, primitive, tag: self.tags[t] });
    }

    fn emit_polygon(&mut self, g: &ShapeGrammar, points: Vec<glam::Vec3>, tag: u32) {
        let tag = self.scene_tag(g, tag);
        self.scene.polygons.push(Polygon { points, tag });
    }

    fn emit_mesh(&mut self, g: &ShapeGrammar, transform: Affine3A, mesh: Mesh, tag: u32) {
        let tag = self.scene_tag(g, tag);
        // Made by this run: a new mesh of the scene (exporters and scorers
        // compare meshes by content, not by identity).
        self.scene.meshes.push(Arc::new(mesh));
        let primitive = Primitive::Mesh((self.scene.meshes.len() - 1) as u32);
        self.scene.instances.push(Instance { transform, primitive, tag });
    }

    fn limit(&self, kind: LimitKind, limits: &Limits) -> Stop {
        ExpressError::Limit { kind, limit: kind.value(limits) }.into()
    }

    fn note(&mut self, text: String) {
        self.scene.note(text);
    }
}

impl ExpressMode<'_> {
    /// The scene's id of grammar tag `tag`, interning it on first use.
    fn scene_tag(&mut self, g: &ShapeGrammar, tag: u32) -> u32 {
        let t = tag as usize;
        if self.tags[t] == UNSEEN {
            self.intern(g, t);
        }
        self.tags[t]
    }

    /// Adds grammar tag `t` to the scene, with its texture if it has one.
    #[cold]
    fn intern(&mut self, g: &ShapeGrammar, t: usize) {
        let id = self.scene.tag(&g.tags[t]);
        self.tags[t] = id;
        if let Some(&Some(k)) = g.tag_textures.get(t) {
            self.scene.set_texture(id, &g.textures[k as usize]);
        }
    }
}

/// Expresses `genome` into `scene`.
pub(crate) fn express(
    g: &ShapeGrammar,
    genome: &Genome,
    limits: &Limits,
    scene: &mut Scene,
) -> Result<(), ExpressError> {
    with_scratch(|scratch| {
        if !g.check.surely_valid(genome, &mut scratch.starts) {
            genome.validate(&g.graph)?;
        }
        if genome.len() > limits.max_genes {
            return Err(ExpressError::Limit { kind: LimitKind::Genes, limit: limits.max_genes });
        }
        let mut tags = std::mem::take(&mut scratch.tags);
        tags.clear();
        tags.resize(g.tags.len(), UNSEEN);
        let mut meshes = std::mem::take(&mut scratch.meshes);
        meshes.clear();
        meshes.resize(g.meshes.len(), UNSEEN);
        let mode = ExpressMode { genome, scene, tags, meshes };
        let (res, mode) = interp::run(g, limits, mode, &mut scratch.stacks);
        (scratch.tags, scratch.meshes) = (mode.tags, mode.meshes);
        match res {
            Ok(()) => Ok(()),
            Err(Stop::Error(e)) => Err(*e),
            Err(Stop::Truncate(kind)) => Err(ExpressError::Limit { kind, limit: kind.value(limits) }),
        }
    })
}

#[cfg(test)]
mod tests {
    use crate::{NoAssets, ShapeGrammar};
    use genform_core::{ExpressError, Generator, Genome, Limits, Rng, Scene, SourceFile};

    fn grammar(src: &str) -> ShapeGrammar {
        crate::compile(&SourceFile::new("t.sg", src), &NoAssets).unwrap().0
    }

    fn express(g: &ShapeGrammar, genome: &Genome, limits: &Limits) -> Result<Scene, ExpressError> {
        let mut scene = Scene::new();
        g.express(genome, limits, &mut scene).map(|()| scene)
    }

    fn same(a: &Scene, b: &Scene) -> bool {
        a.instances == b.instances && a.tags == b.tags
    }

    const SHIP: &str = "S { B; }
        B { param s: vec3 uniform(0.6, 1.5); slot n: B p 0.6; slot w: W p 0.5;
            scale(s); translate(0, 0, sz / 2); box; [ translate(0, 0, sz / 2); n; ]
            mirror(x) { translate(sx / 2, 0, 0); w; } }
        W { param m: uniform(-0.5, 0.5); tag(\"wing\"); translate(sx * m, 0, 0); cone; }";
    const TOWER: &str = "T { param h: int(1, 6); size(1, h, 1);
        repeat(y, 1) { split(x) { 1r: box | 0.5: { tag(\"gap\"); sphere; } | 1r: box } } }";

    /// The per-thread buffers carry nothing from one run to the next, not
    /// even from a run stopped half-way by an error.
    #[test]
    fn reused_buffers_leave_no_trace() {
        let (ship, tower) = (grammar(SHIP), grammar(TOWER));
        let limits = Limits::default();
        let genomes: Vec<(&ShapeGrammar, Genome)> = (0..8)
            .flat_map(|seed| {
                let mut rng = Rng::from_seed(seed);
                [&ship, &tower].map(|g| (g, g.sample(&mut rng, &limits).unwrap().genome))
            })
            .collect();
        let first: Vec<Scene> = genomes.iter().map(|(g, genome)| express(g, genome, &limits).unwrap()).collect();
        assert!(first.iter().any(|s| s.instances.len() > 4), "the test needs some larger scenes");
        let tight = Limits { max_primitives: 3, ..limits };
        for ((g, genome), want) in genomes.iter().zip(&first).rev() {
            let stopped = express(g, genome, &tight);
            assert_eq!(stopped.is_err(), want.instances.len() > 3);
            assert!(same(&express(g, genome, &limits).unwrap(), want));
        }
    }

    /// Threads express concurrently, each with its own buffers.
    #[test]
    fn threads_express_independently() {
        let ship = grammar(SHIP);
        let limits = Limits::default();
        let genomes: Vec<Genome> =
            (0..16).map(|seed| ship.sample(&mut Rng::from_seed(seed), &limits).unwrap().genome).collect();
        let want: Vec<Scene> = genomes.iter().map(|genome| express(&ship, genome, &limits).unwrap()).collect();
        std::thread::scope(|s| {
            for t in 0..4 {
                let (ship, genomes, want) = (&ship, &genomes, &want);
                s.spawn(move || {
                    for round in 0..20 {
                        let i = (t * 7 + round * 3) % genomes.len();
                        assert!(same(&express(ship, &genomes[i], &limits).unwrap(), &want[i]));
                    }
                });
            }
        });
    }
}
