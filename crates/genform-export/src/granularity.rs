//! How finely GLB and OBJ split a model into nodes and objects.

use std::fmt;
use std::str::FromStr;

/// Above this many instances and polygons [`Granularity::Auto`] merges: a DCC tool such
/// as Blender makes one object per glTF node or OBJ object, and a few
/// dozen objects is about what a user can still pick through by hand.
pub const AUTO_MERGE_ABOVE: usize = 32;

/// How a model's instances are split into GLB nodes or OBJ objects.
///
/// Only instances (boxes, frusta, spheres, mesh assets …) and polygons are
/// regrouped; polylines, block grids and surfaces keep their own nodes and
/// objects in every mode.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Granularity {
    /// [`Granularity::Merged`] above [`AUTO_MERGE_ABOVE`] instances and
    /// polygons together, else
    /// [`Granularity::Instanced`].
    #[default]
    Auto,
    /// One world-space mesh for the whole model with one part per material:
    /// GLB one node `model` whose mesh has one primitive per (tag,
    /// double-sided); OBJ one object `o model` with one group `g <tag>` per
    /// tag.
    Merged,
    /// One world-space mesh per tag: GLB one node per tag, named by the tag;
    /// OBJ one object `o <tag>` per tag.
    PerTag,
    /// One node per instance. GLB nodes share one mesh per (primitive,
    /// tag) and carry the instance transform as their matrix (the layout
    /// before granularity existed); OBJ has no instancing, so it writes one
    /// object per instance with its own world-space copy of the vertices.
    Instanced,
}

impl Granularity {
    /// Every mode, in the order of [`Granularity::names`].
    pub const ALL: [Granularity; 4] =
        [Granularity::Auto, Granularity::Merged, Granularity::PerTag, Granularity::Instanced];

    /// The names [`FromStr`] accepts and [`fmt::Display`] writes.
    pub fn names() -> &'static [&'static str] {
        &["auto", "merged", "tag", "instanced"]
    }

    /// The concrete mode for a scene of `instances` instances and polygons: `Auto`
    /// decided, the others unchanged.
    pub fn resolve(self, instances: usize) -> Granularity {
        match self {
            Granularity::Auto if instances > AUTO_MERGE_ABOVE => Granularity::Merged,
            Granularity::Auto => Granularity::Instanced,
            g => g,
        }
    }
}

impl fmt::Display for Granularity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let i = Granularity::ALL.iter().position(|g| g == self).unwrap_or(0);
        f.write_str(Granularity::names()[i])
    }
}

impl FromStr for Granularity {
    type Err = String;

    /// Parses one of [`Granularity::names`] (case-insensitive); `primitive`
    /// is taken as `instanced` (one node per primitive).
    fn from_str(s: &str) -> Result<Granularity, String> {
        let s = s.trim().to_ascii_lowercase();
        if s == "primitive" {
            return Ok(Granularity::Instanced);
        }
        match Granularity::names().iter().position(|n| *n == s) {
            Some(i) => Ok(Granularity::ALL[i]),
            None => Err(format!("unknown granularity `{s}`; known: {}", Granularity::names().join(", "))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_names_list_the_known() {
        for g in Granularity::ALL {
            assert_eq!(g.to_string().parse::<Granularity>(), Ok(g));
        }
        assert_eq!("Primitive".parse::<Granularity>(), Ok(Granularity::Instanced));
        assert_eq!(" TAG ".parse::<Granularity>(), Ok(Granularity::PerTag));
        let e = "objects".parse::<Granularity>().unwrap_err();
        assert_eq!(e, "unknown granularity `objects`; known: auto, merged, tag, instanced");
    }

    #[test]
    fn auto_merges_only_above_the_threshold() {
        assert_eq!(Granularity::Auto.resolve(AUTO_MERGE_ABOVE), Granularity::Instanced);
        assert_eq!(Granularity::Auto.resolve(AUTO_MERGE_ABOVE + 1), Granularity::Merged);
        assert_eq!(Granularity::PerTag.resolve(10_000), Granularity::PerTag);
        assert_eq!(Granularity::Merged.resolve(0), Granularity::Merged);
    }
}
