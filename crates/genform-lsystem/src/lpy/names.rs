//! L-Py's predefined module names, PlantGL's turtle defaults and the
//! names the translation adds.

/// The global that holds L-Py's active group (`useGroup`, `getGroup()`).
pub(super) const GROUP: &str = "lpy_group";

/// The module that stands for an empty axiom in the `.ls` text.
pub(super) const EMPTY: &str = "lpy_empty_axiom";

/// L-Py's predefined long names that are another spelling of a short
/// one (src/cpp/predefinedmodules.cpp): one module class, which L-Py keeps
/// and prints under the short name, so the translation writes that. PlantGL
/// calls `/` RollL and `\` RollR. (`any`, `surface` and `GetModule` are
/// kept long: `*`, `~` and `$` mean other things in `.ls` text.)
pub(super) const SPELLINGS: &[(&str, &str)] = &[
    ("SB", "["),
    ("EB", "]"),
    ("GetPos", "?P"),
    ("GetHead", "?H"),
    ("GetUp", "?U"),
    ("GetLeft", "?L"),
    ("GetRight", "?R"),
    ("GetFrame", "?F"),
    ("StartGC", "@Gc"),
    ("EndGC", "@Ge"),
    ("BP", "{"),
    ("EP", "}"),
    ("PP", "."),
    ("MoveTo", "@M"),
    ("SetHead", "@R"),
    ("Left", "+"),
    ("Right", "-"),
    ("Up", "^"),
    ("Down", "&"),
    ("RollL", "/"),
    ("RollR", "\\"),
    ("TurnAround", "|"),
    ("RollToVert", "@v"),
    ("RollToHorizontal", "@h"),
    ("Sphere", "@O"),
    ("Box", "@B"),
    ("Quad", "@b"),
    ("Circle", "@o"),
    ("Label", "@L"),
    ("IncWidth", "_"),
    ("DecWidth", "!"),
    ("IncColor", ";"),
    ("DecColor", ","),
    ("DivScale", "@Dd"),
    ("MultScale", "@Di"),
    ("SetScale", "@D"),
    ("PglShape", "@g"),
    ("Elasticity", "@Ts"),
    ("Tropism", "@Tp"),
    ("StartScreenProjection", "@2D"),
    ("EndScreenProjection", "@3D"),
    ("Cut", "%"),
    ("GetIterator", "?I"),
    ("TextureVCoeff", "TextureVScale"),
];

/// Predefined long names of modules of their own that draw as a short one:
/// L-Py's SetWidth and SetColor set what `!` and `,` decrease.
pub(super) const DRAWS_AS: &[(&str, &str)] = &[("SetWidth", "!"), ("SetColor", ",")];

/// L-Py's other predefined long names: one module each, not drawn by
/// genform (plain symbols).
pub(super) const OTHER_NAMES: &[&str] = &[
    "nF",
    "MoveRel",
    "LineTo",
    "OLineTo",
    "Pinpoint",
    "LineRel",
    "OLineRel",
    "PinpointRel",
    "EulerAngles",
    "iRollL",
    "iRollR",
    "InterpolateColors",
    "TextureBaseColor",
    "InterpolateTextureBaseColors",
    "Frame",
    "Arrow",
    "SetContour",
    "SectionResolution",
    "SetGuide",
    "EndGuide",
    "Sweep",
    "PositionOnGuide",
    "TextureScale",
    "TextureUScale",
    "TextureVScale",
    "TextureTranslation",
    "TextureRotation",
    "TextureTransformation",
    "LeftReflection",
    "UpReflection",
    "HeadingReflection",
    "GetModule",
    "MouseIns",
];

/// Every predefined long name: read as one module wherever it stands.
pub(super) fn long_names() -> impl Iterator<Item = &'static str> {
    SPELLINGS.iter().chain(DRAWS_AS).map(|(n, _)| *n).chain(OTHER_NAMES.iter().copied())
}

/// The name L-Py keeps for a module name (itself unless a spelling).
pub(super) fn canonical(name: &str) -> &str {
    SPELLINGS.iter().find(|(n, _)| *n == name).map_or(name, |(_, c)| c)
}

/// The settings every translated file starts with: PlantGL's defaults.
pub(super) const PRELUDE: &str = "angle: 60\nstep: 1\nheading: +y\nview: 3d\nwidth: 0.1\nwidth_unit: 2\n";
