//! L-Py's predefined module names, PlantGL's turtle defaults and the
//! names the translation adds.

/// The global that holds L-Py's active group (`useGroup`, `getGroup()`).
pub(super) const GROUP: &str = "lpy_group";

/// The module that stands for an empty axiom in the `.ls` text.
pub(super) const EMPTY: &str = "lpy_empty_axiom";

/// L-Py's predefined long module names that genform draws, with the
/// one-character (or `@`) alias whose turtle command they share. PlantGL
/// calls `/` RollL and `\` RollR.
pub(super) const ALIASES: &[(&str, &str)] = &[
    ("Left", "+"),
    ("Right", "-"),
    ("Up", "^"),
    ("Down", "&"),
    ("RollL", "/"),
    ("RollR", "\\"),
    ("TurnAround", "|"),
    ("IncWidth", "_"),
    ("DecWidth", "!"),
    ("SetWidth", "!"),
    ("IncColor", ";"),
    ("DecColor", ","),
    ("SetColor", ","),
    ("SetHead", "@R"),
    ("Sphere", "@O"),
    ("StartGC", "@Gc"),
    ("EndGC", "@Ge"),
    ("BP", "{"),
    ("EP", "}"),
    ("PP", "."),
    ("SetScale", "@D"),
    ("MultScale", "@Di"),
    ("DivScale", "@Dd"),
];

/// L-Py's other predefined long names: one module each, not drawn by
/// genform (plain symbols).
pub(super) const OTHER_NAMES: &[&str] = &[
    "nF",
    "MoveTo",
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
    "RollToVert",
    "RollToHorizontal",
    "Box",
    "Quad",
    "Circle",
    "Label",
    "InterpolateColors",
    "TextureBaseColor",
    "InterpolateTextureBaseColors",
    "PglShape",
    "Frame",
    "Arrow",
    "Elasticity",
    "Tropism",
    "SetContour",
    "SectionResolution",
    "SetGuide",
    "EndGuide",
    "Sweep",
    "PositionOnGuide",
    "TextureScale",
    "TextureUScale",
    "TextureVScale",
    "TextureVCoeff",
    "TextureTranslation",
    "TextureRotation",
    "TextureTransformation",
    "LeftReflection",
    "UpReflection",
    "HeadingReflection",
    "GetPos",
    "GetHead",
    "GetUp",
    "GetLeft",
    "GetRight",
    "GetFrame",
    "StartScreenProjection",
    "EndScreenProjection",
];

/// The settings every translated file starts with: PlantGL's defaults.
pub(super) const PRELUDE: &str = "angle: 60\nstep: 1\nheading: +y\nview: 3d\nwidth: 0.1\nwidth_unit: 2\n";
