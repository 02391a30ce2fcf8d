//! What `genform sample` asks of a formalism ([`SampleRequest`]) and the
//! one table of its options ([`SAMPLE_OPTIONS`]): the command line's
//! flags, the Python package's keyword arguments and the studio's sample
//! options are all made from it, and every value is checked here the same
//! way whichever door it came through ([`SampleRequest::set`]).

use anyhow::{Result, anyhow, bail};
use genform_export::Granularity;
use serde_json::Value;
use std::path::PathBuf;

use super::scene_keys::LimitOverrides;

/// Stream id of `sample` (so other verbs' streams never coincide with it).
pub(crate) const SAMPLE_STREAM: u64 = 0x5A4D_504C;

/// The random stream of sample seed `seed`; evaluations that grow
/// phenotypes use seed 0's, so `genform sample best.gr8` grows the same.
pub(crate) fn sample_rng(seed: u64) -> genform_core::Rng {
    genform_core::Rng::stream(seed, &[SAMPLE_STREAM])
}

/// Flags of `genform sample` every formalism accepts.
pub const COMMON_SAMPLE_OPTIONS: &[&str] = &["--seed", "--out", "--granularity"];

/// How an option's value is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ValueKind {
    /// A whole number from 0 to `max`.
    Count {
        /// The largest value.
        max: u64,
    },
    /// A whole number from `min` to `max`.
    Integer {
        /// The smallest value.
        min: i64,
        /// The largest value.
        max: i64,
    },
    /// Text (which may start with `-`).
    Text,
    /// A file the command reads.
    InputFile,
    /// A file the command writes.
    OutputFile,
    /// On when given.
    Flag,
    /// One of the names.
    Choice(&'static [&'static str]),
}

/// One option of `genform sample`: `--NAME` on the command line, `NAME`
/// (with `_` for `-`) as a Python keyword and a studio option.
pub struct SampleOption {
    /// The name, e.g. `max-modules`.
    pub name: &'static str,
    /// A one-letter flag, e.g. `o` for `out`.
    pub short: Option<char>,
    /// What the value is called in help texts, e.g. `N`.
    pub value_name: &'static str,
    /// How the value is written.
    pub kind: ValueKind,
    /// The default when not given, as shown in help texts.
    pub default: Option<&'static str>,
    /// What it does, for help texts.
    pub help: &'static str,
    /// Whether the studio offers it (options naming files it would write
    /// or read outside its roots are the command line's and Python's).
    pub studio: bool,
    set: fn(&mut SampleRequest, Parsed),
}

/// A checked option value.
enum Parsed {
    Number(u64),
    Signed(i64),
    Text(String),
    Path(PathBuf),
    On(bool),
}

impl Parsed {
    fn number(&self) -> u64 {
        if let Parsed::Number(n) = self { *n } else { 0 }
    }
    fn text(self) -> String {
        match self {
            Parsed::Text(t) => t,
            Parsed::Path(p) => p.display().to_string(),
            _ => String::new(),
        }
    }
    fn path(self) -> PathBuf {
        match self {
            Parsed::Path(p) => p,
            Parsed::Text(t) => PathBuf::from(t),
            _ => PathBuf::new(),
        }
    }
}

/// Every option of `genform sample`, common ones first.
pub static SAMPLE_OPTIONS: &[SampleOption] = &[
    SampleOption {
        name: "seed",
        short: None,
        value_name: "N",
        kind: ValueKind::Count { max: u64::MAX },
        default: Some("0"),
        help: "Random seed; the same seed gives the same model.",
        studio: false,
        set: |r, v| r.seed = v.number(),
    },
    SampleOption {
        name: "out",
        short: Some('o'),
        value_name: "OUT",
        kind: ValueKind::OutputFile,
        default: None,
        help: "Output file; the format follows the extension (.glb .obj .ply .stl .png .svg; block grammars also \
               .schem .litematic .vox .mca; graph grammars .yaml). Without it nothing is written: the model's \
               summary goes to stdout.",
        studio: false,
        set: |r, v| r.out = Some(v.path()),
    },
    SampleOption {
        name: "granularity",
        short: None,
        value_name: "MODE",
        kind: ValueKind::Choice(&["auto", "merged", "tag", "instanced", "primitive"]),
        default: Some("auto"),
        help: ".glb/.obj: how the model is split into nodes/objects: `merged` (one mesh, a part per material), \
               `tag` (one per tag), `instanced` (one per primitive; GLB nodes share meshes); `auto`: merged above \
               32 primitives, else instanced.",
        studio: true,
        set: |r, v| r.granularity = v.text().parse().unwrap_or_default(),
    },
    SampleOption {
        name: "steps",
        short: None,
        value_name: "N",
        kind: ValueKind::Count { max: crate::caps::MAX_STEPS },
        default: None,
        help: "L-systems, graph grammars and HEMLS: derivation steps (default: the file's `derivation:`; HEMLS: \
               the environment's `steps`, else 4).",
        studio: true,
        set: |r, v| r.steps = Some(v.number() as u32),
    },
    SampleOption {
        name: "max-modules",
        short: None,
        value_name: "N",
        kind: ValueKind::Count { max: usize::MAX as u64 },
        default: None,
        help: "L-systems: longest string a derivation may produce (default: the file's `max_modules:`, else \
               5,000,000); graph grammars: most elements (vertices + edges, default 1,000,000).",
        studio: true,
        set: |r, v| r.max_modules = Some(v.number() as usize),
    },
    SampleOption {
        name: "string-out",
        short: None,
        value_name: "FILE",
        kind: ValueKind::OutputFile,
        default: None,
        help: "L-systems: also write the derived module string to this text file.",
        studio: false,
        set: |r, v| r.string_out = Some(v.path()),
    },
    SampleOption {
        name: "box",
        short: None,
        value_name: "X0,Y0,Z0,X1,Y1,Z1",
        kind: ValueKind::Text,
        default: None,
        help: "Box-split grammars: the box to derive in, two opposite corners (inclusive) `x0,y0,z0,x1,y1,z1`.",
        studio: true,
        set: |r, v| r.box_corners = Some(v.text()),
    },
    SampleOption {
        name: "world",
        short: None,
        value_name: "REGION",
        kind: ValueKind::InputFile,
        default: None,
        help: "Box-split grammars: observe this Minecraft region file (r.X.Z.mca) or folder of region files; \
               `--out x.mca` writes into a copy of it.",
        studio: false,
        set: |r, v| r.world = Some(v.path()),
    },
    SampleOption {
        name: "trace",
        short: None,
        value_name: "FILE.json",
        kind: ValueKind::OutputFile,
        default: None,
        help: "Box-split grammars: write the derivation trace (choices, failures, backtracks) as JSON.",
        studio: false,
        set: |r, v| r.trace = Some(v.path()),
    },
    SampleOption {
        name: "schem-version",
        short: None,
        value_name: "2|3",
        kind: ValueKind::Integer { min: 2, max: 3 },
        default: Some("2"),
        help: "Box-split grammars: Sponge schematic version of `.schem` output.",
        studio: true,
        set: |r, v| r.schem_version = if let Parsed::Signed(n) = v { n as u8 } else { 2 },
    },
    SampleOption {
        name: "data-version",
        short: None,
        value_name: "N",
        kind: ValueKind::Integer { min: i32::MIN as i64, max: i32::MAX as i64 },
        default: Some("3955"),
        help: "Box-split grammars: Minecraft DataVersion written into `.schem` and `.litematic` files (3955 = \
               1.21.1; 3337 = 1.19.4).",
        studio: true,
        set: |r, v| r.data_version = if let Parsed::Signed(n) = v { n as i32 } else { 3955 },
    },
    SampleOption {
        name: "genome-out",
        short: None,
        value_name: "G.json",
        kind: ValueKind::OutputFile,
        default: None,
        help: "Also save the derivation tree (genome) as JSON, for `genform derive`.",
        studio: false,
        set: |r, v| r.genome_out = Some(v.path()),
    },
    SampleOption {
        name: "env",
        short: None,
        value_name: "ENV.toml",
        kind: ValueKind::InputFile,
        default: None,
        help: "HEMLS (.gr8): the environment file (TOML: growth settings, charges, gravity, boundaries); without \
               it the surface grows with Genr8's defaults.",
        studio: true,
        set: |r, v| r.env = Some(v.path()),
    },
    SampleOption {
        name: "every-step",
        short: None,
        value_name: "",
        kind: ValueKind::Flag,
        default: None,
        help: "HEMLS (.gr8): write every derivation step, one mesh per step (`name-step0.obj` …) and, for \
               .png/.svg, one picture with a labelled panel per step, all at one scale.",
        studio: false,
        set: |r, v| r.every_step = matches!(v, Parsed::On(true)),
    },
    SampleOption {
        name: "smooth",
        short: None,
        value_name: "K",
        kind: ValueKind::Count { max: u32::MAX as u64 },
        default: None,
        help: "HEMLS (.gr8): apply K Catmull–Clark subdivision steps to the final surface (at most 6).",
        studio: true,
        set: |r, v| r.smooth = Some(v.number() as u32),
    },
    SampleOption {
        name: "footprints",
        short: None,
        value_name: "LOTS.geojson|LOTS.gpkg[#LAYER]|LOTS.obj",
        kind: ValueKind::InputFile,
        default: None,
        help: "Shape grammars (.sg): derive once per lot of this GeoJSON file (Polygon and MultiPolygon features; \
               longitude/latitude per RFC 7946, EPSG:3857 or metres, built around a local origin), GeoPackage \
               layer (`FILE.gpkg#LAYER`; the file's only polygon layer without `#LAYER`; its CRS read the same \
               way) or OBJ file (faces facing up), lot k with seed SEED + k, instead of the `footprints` the \
               grammar declares.",
        studio: true,
        set: |r, v| r.footprints = Some(v.path()),
    },
    SampleOption {
        name: "max-genes",
        short: None,
        value_name: "N",
        kind: ValueKind::Count { max: usize::MAX as u64 },
        default: None,
        help: "Most genes (rule applications) in a derivation.",
        studio: true,
        set: |r, v| r.limits.max_genes = Some(v.number() as usize),
    },
    SampleOption {
        name: "max-depth",
        short: None,
        value_name: "N",
        kind: ValueKind::Count { max: usize::MAX as u64 },
        default: None,
        help: "Deepest derivation.",
        studio: true,
        set: |r, v| r.limits.max_depth = Some(v.number() as usize),
    },
    SampleOption {
        name: "max-primitives",
        short: None,
        value_name: "N",
        kind: ValueKind::Count { max: usize::MAX as u64 },
        default: None,
        help: "Most primitives in the model.",
        studio: true,
        set: |r, v| r.limits.max_primitives = Some(v.number() as usize),
    },
];

/// The option called `name` (`--max-modules`, `max-modules` and
/// `max_modules` alike).
pub fn sample_option(name: &str) -> Option<&'static SampleOption> {
    let name = name.trim_start_matches("--").replace('_', "-");
    SAMPLE_OPTIONS.iter().find(|o| o.name == name)
}

impl SampleOption {
    /// `value` checked as this option's: a JSON number, boolean, string or
    /// (for `box`) a list of corners; numbers may also come as text (the
    /// command line's). Files are resolved by `resolve`.
    /// `given`: the name as the door wrote it, for messages.
    fn parse(&self, given: &str, value: &Value, resolve: &dyn Fn(&str) -> Result<PathBuf>) -> Result<Parsed> {
        let bad = |what: &str| anyhow!("option `{given}` must be {what}, not {value}");
        let whole = || -> Option<i128> {
            match value {
                Value::Number(n) => n
                    .as_i64()
                    .map(i128::from)
                    .or_else(|| n.as_u64().map(i128::from))
                    .or_else(|| n.as_f64().filter(|f| f.fract() == 0.0 && f.abs() < 1e30).map(|f| f as i128)),
                Value::String(s) => s.trim().parse::<i128>().ok(),
                _ => None,
            }
        };
        Ok(match self.kind {
            ValueKind::Count { max } => match whole() {
                Some(n) if n >= 0 && n <= i128::from(max) => Parsed::Number(n as u64),
                _ => return Err(bad(&format!("a whole number 0..={max}"))),
            },
            ValueKind::Integer { min, max } => match whole() {
                Some(n) if n >= i128::from(min) && n <= i128::from(max) => Parsed::Signed(n as i64),
                _ if min == 2 && max == 3 => return Err(bad("2 or 3")),
                _ => return Err(bad(&format!("a whole number {min}..={max}"))),
            },
            ValueKind::Text => match value {
                Value::String(s) => Parsed::Text(s.clone()),
                // `box` as a list of corners (Python's `box=[0, 0, 0, 9, 9, 9]`).
                Value::Array(items) => {
                    let parts: Option<Vec<String>> = items.iter().map(|i| i.as_i64().map(|n| n.to_string())).collect();
                    Parsed::Text(parts.ok_or_else(|| bad("text or a list of whole numbers"))?.join(","))
                }
                _ => return Err(bad("text")),
            },
            ValueKind::InputFile | ValueKind::OutputFile => match value {
                // A GeoPackage layer (`lots.gpkg#buildings`) is no part of
                // the file's name: the door resolves the file alone.
                Value::String(s) => match crate::footprints::split_layer(std::path::Path::new(s)) {
                    (file, Some(layer)) => {
                        let mut path = resolve(&file.to_string_lossy())?.into_os_string();
                        path.push(format!("#{layer}"));
                        Parsed::Path(path.into())
                    }
                    (_, None) => Parsed::Path(resolve(s)?),
                },
                _ => return Err(bad("a file name")),
            },
            ValueKind::Flag => match value {
                Value::Bool(b) => Parsed::On(*b),
                _ => return Err(bad("true or false")),
            },
            ValueKind::Choice(names) => match value {
                Value::String(s) if names.contains(&s.trim().to_ascii_lowercase().as_str()) => {
                    Parsed::Text(s.trim().to_ascii_lowercase())
                }
                _ => return Err(bad(&format!("one of {}", names.join(", ")))),
            },
        })
    }
}

/// What `genform sample` asks of a formalism: the common settings and the
/// value of every formalism's options (each formalism reads only those it
/// declares in its `sample_options`; the table's check has refused the
/// others).
#[derive(Clone, Debug)]
pub struct SampleRequest {
    /// Random seed.
    pub seed: u64,
    /// `--out`: the model file.
    pub out: Option<PathBuf>,
    /// The long flags given (defaults not included).
    pub given: Vec<String>,
    /// `--granularity`: how meshes are split into nodes and objects.
    pub granularity: Granularity,
    /// `--genome-out`: where to save the genome.
    pub genome_out: Option<PathBuf>,
    /// Derive through the generator graph, so the sample carries its
    /// genome ([`Sample::genome`](super::Sample::genome)) as `--genome-out`
    /// would save it (doors that keep models for `derive` and `evolve`).
    pub keep_genome: bool,
    /// `--max-genes`, `--max-depth`, `--max-primitives`.
    pub limits: LimitOverrides,
    /// `--steps`: derivation steps.
    pub steps: Option<u32>,
    /// `--max-modules`: longest string (L-systems), most elements (graph grammars).
    pub max_modules: Option<usize>,
    /// `--string-out`: where to write the derived string.
    pub string_out: Option<PathBuf>,
    /// `--box`: the box to derive in, as written.
    pub box_corners: Option<String>,
    /// `--world`: a region file or folder to observe.
    pub world: Option<PathBuf>,
    /// `--trace`: where to write the derivation trace.
    pub trace: Option<PathBuf>,
    /// `--schem-version`: Sponge schematic version.
    pub schem_version: u8,
    /// `--data-version`: Minecraft DataVersion of block files.
    pub data_version: i32,
    /// `--env`: a growth environment file (HEMLS).
    pub env: Option<PathBuf>,
    /// `--every-step`: write every derivation step (HEMLS).
    pub every_step: bool,
    /// `--smooth`: Catmull–Clark steps on the final surface (HEMLS).
    pub smooth: Option<u32>,
    /// `--footprints`: lots to derive a shape grammar on, one derivation
    /// each (GeoJSON, GeoPackage — `lots.gpkg#LAYER` — or OBJ).
    pub footprints: Option<PathBuf>,
}

impl SampleRequest {
    /// A request for seed `seed` with every option at its default (no
    /// files written, Sponge schematic v2, DataVersion 3955 = 1.21.1).
    pub fn new(seed: u64) -> SampleRequest {
        SampleRequest {
            seed,
            out: None,
            given: Vec::new(),
            granularity: Granularity::Auto,
            genome_out: None,
            keep_genome: false,
            limits: LimitOverrides::default(),
            steps: None,
            max_modules: None,
            string_out: None,
            box_corners: None,
            world: None,
            trace: None,
            schem_version: 2,
            data_version: 3955,
            env: None,
            every_step: false,
            smooth: None,
            footprints: None,
        }
    }

    /// Sets the option `name` of [`SAMPLE_OPTIONS`] to `value` (checked
    /// there; file names resolved by `resolve`) and notes it as given.
    pub fn set(&mut self, name: &str, value: &Value, resolve: &dyn Fn(&str) -> Result<PathBuf>) -> Result<()> {
        let Some(option) = sample_option(name) else {
            let names: Vec<String> = SAMPLE_OPTIONS.iter().map(|o| o.name.replace('-', "_")).collect();
            bail!("unknown option `{name}`; the sample options are {}", names.join(", "));
        };
        let parsed = option.parse(name.trim_start_matches("--"), value, resolve)?;
        if !matches!(parsed, Parsed::On(false)) {
            (option.set)(self, parsed);
            let flag = format!("--{}", option.name);
            if !self.given.contains(&flag) {
                self.given.push(flag);
            }
        }
        Ok(())
    }

    /// The files the request names to read (`--env`, `--footprints`,
    /// `--world`), admitted through the file gate (and recorded as inputs
    /// of the command) before anything is derived.
    pub fn admit_inputs(&self) -> anyhow::Result<()> {
        let named = [("environment", &self.env), ("footprints", &self.footprints), ("world", &self.world)];
        for (what, path) in named {
            if let Some(p) = path {
                crate::gate::admit_read(&crate::footprints::split_layer(p).0, what)?;
            }
        }
        Ok(())
    }

    /// The files the request writes, by flag: each is refused before
    /// anything runs when it is one of the command's inputs
    /// ([`crate::refuse_outputs`]).
    pub fn outputs(&self) -> Vec<(&'static str, &std::path::Path)> {
        let named = [
            ("--out", &self.out),
            ("--string-out", &self.string_out),
            ("--trace", &self.trace),
            ("--genome-out", &self.genome_out),
        ];
        named.into_iter().filter_map(|(flag, p)| Some((flag, p.as_deref()?))).collect()
    }

    /// The export settings of `--out`.
    pub fn export(&self) -> genform_export::ExportOptions {
        genform_export::ExportOptions { granularity: self.granularity, ..Default::default() }
    }

    /// The random stream of this sample.
    pub fn rng(&self) -> genform_core::Rng {
        sample_rng(self.seed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn as_is(s: &str) -> Result<PathBuf> {
        Ok(PathBuf::from(s))
    }

    #[test]
    fn options_take_numbers_text_and_lists_from_every_door() {
        let mut r = SampleRequest::new(0);
        r.set("--steps", &Value::from("12"), &as_is).unwrap();
        r.set("max_modules", &Value::from(500), &as_is).unwrap();
        r.set("box", &serde_json::json!([0, 1, 2, 9, 9, 9]), &as_is).unwrap();
        r.set("every_step", &Value::Bool(true), &as_is).unwrap();
        r.set("schem-version", &Value::from(3.0), &as_is).unwrap();
        r.set("granularity", &Value::from("Tag"), &as_is).unwrap();
        assert_eq!((r.steps, r.max_modules, r.box_corners.as_deref()), (Some(12), Some(500), Some("0,1,2,9,9,9")));
        assert_eq!((r.every_step, r.schem_version, r.granularity), (true, 3, Granularity::PerTag));
        assert_eq!(r.given, ["--steps", "--max-modules", "--box", "--every-step", "--schem-version", "--granularity"]);
        let e = r.set("steps", &Value::from(-1), &as_is).unwrap_err().to_string();
        assert_eq!(e, "option `steps` must be a whole number 0..=1000000, not -1");
        let e = r.set("schem_version", &Value::from(4), &as_is).unwrap_err().to_string();
        assert_eq!(e, "option `schem_version` must be 2 or 3, not 4", "named as the door wrote it");
        let e = r.set("stpes", &Value::from(1), &as_is).unwrap_err().to_string();
        assert!(e.starts_with("unknown option `stpes`; the sample options are seed, out, granularity, steps"), "{e}");
        r.set("every-step", &Value::Bool(false), &as_is).unwrap();
        assert!(r.every_step, "false leaves the default and is not given");
    }

    #[test]
    fn files_go_through_the_doors_resolver() {
        let mut r = SampleRequest::new(0);
        let refuse = |s: &str| -> Result<PathBuf> { bail!("`{s}` is outside the roots") };
        let e = r.set("env", &Value::from("/etc/x.toml"), &refuse).unwrap_err().to_string();
        assert_eq!(e, "`/etc/x.toml` is outside the roots");
        r.set("env", &Value::from("e.toml"), &|s: &str| Ok(PathBuf::from("/root").join(s))).unwrap();
        assert_eq!(r.env, Some(PathBuf::from("/root/e.toml")));
        // A GeoPackage layer is no part of the file the resolver sees.
        let seen = std::cell::RefCell::new(Vec::new());
        let root = |s: &str| {
            seen.borrow_mut().push(s.to_string());
            Ok(PathBuf::from("/root").join(s))
        };
        r.set("footprints", &Value::from("lots.gpkg#buildings"), &root).unwrap();
        assert_eq!(r.footprints, Some(PathBuf::from("/root/lots.gpkg#buildings")));
        assert_eq!(*seen.borrow(), ["lots.gpkg"]);
    }
}
