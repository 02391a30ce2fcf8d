//! Targets and weights: how [`SurfaceMeasures`] become one fitness.
//!
//! The paper's total is `F = Σ_i w_i F_i` with user weights `w_i` and a
//! user target per criterion, but it does not say how the target enters
//! (reference §8, \[D\]). Here each criterion with weight `w_i > 0`, target
//! `T_i` and floor `ε_i` ([`SurfaceGoal`]) has the error
//!
//! `e_i = |F_i − T_i| / max(|T_i|, ε_i)`
//!
//! (relative error, measured in units of `ε_i` when the target is near 0),
//! and the errors combine in one of two forms ([`SurfaceForm`], the scene's
//! `[surface] form`):
//!
//! - **bounded** (the default, genform's departure from the paper):
//!   `fitness = Σ_i w_i / (1 + e_i)`, so each criterion's score
//!   `1 / (1 + e_i)` lies in (0, 1], is 1 exactly on target and falls
//!   strictly as the measure moves away. The fitness lies in [0, Σ w_i]:
//!   [`SurfaceScorer::best`] on every target, 0 the worst.
//! - **paper**: the paper's weighted sum of the criteria, each criterion
//!   being its error: Genr8 minimises `Σ_i w_i e_i`, and since genform's
//!   optimizers maximise, `fitness = −Σ_i w_i e_i`, in (−∞, 0], 0 on every
//!   target. The contribution of a criterion is `−w_i e_i`, linear in its
//!   distance from the target.
//!
//! Why the bounded form is the default rather than the paper's sum:
//!
//! - Growth is exponential in the number of steps, so errors span orders of
//!   magnitude (size 400 against a target of 10 is e = 39). In an unbounded
//!   sum one such criterion swamps the others, and tournaments then rank
//!   individuals by it alone; bounded, a criterion can never cost more than
//!   its weight, so the weights keep the paper's meaning of relative
//!   importance and trade-offs between criteria stay visible to selection.
//! - Each criterion's score is strictly decreasing in its error, so
//!   tournament selection and a random-search baseline (both rank-based)
//!   still tell any two errors apart, however large.
//! - Roulette selection weighs `fitness − worst`: with an unbounded form a
//!   single blown-up individual would squeeze everyone else's weights
//!   together; here the range is fixed.
//! - The worst is representable: a valid surface scores ≥ 0 (a non-finite
//!   measure scores its criterion exactly 0), so any invalid marker below 0
//!   — genform-evolve's convention is a non-finite fitness — ranks below
//!   every valid surface; and `fitness / best` is a fraction in [0, 1] for
//!   reports. In the paper form a non-finite measure has an infinite error,
//!   so such a surface scores −∞ and ranks with the invalid individuals.
//!
//! The price: far from a target the score is flat (its slope is
//! `1/(1 + e)²`), so roulette pressure among very poor individuals is weak;
//! the paper form keeps a constant slope `w_i` there.

use super::criterion::SurfaceCriterion;
use super::measures::SurfaceMeasures;
use genform_core::scene::Scene;
use serde::{Deserialize, Serialize};
use std::fmt;

/// Largest weight of a criterion: weights are relative, and past this the
/// weighted sum loses the precision of the small terms.
pub const MAX_WEIGHT: f64 = 1e9;

/// The target, weight and error floor of one criterion, as written in a
/// scene's `[surface]` table: `size = { target = 10, weight = 1 }`.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SurfaceGoal {
    /// The value the measure should have (`T_i`).
    pub target: f64,
    /// Importance `w_i ≥ 0` (default 1 when the criterion is given; a
    /// criterion left out of the table has weight 0 and is skipped).
    #[serde(default = "one")]
    pub weight: f64,
    /// The error floor `ε_i > 0`: the error is `|F − T| / max(|T|, ε)`.
    /// Default [`SurfaceCriterion::default_floor`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub floor: Option<f64>,
}

fn one() -> f64 {
    1.0
}

/// How the criteria's errors `e_i` combine into one fitness: the scene's
/// `[surface] form` (see the [module](self) docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum SurfaceForm {
    /// `Σ w_i / (1 + e_i)`, in [0, Σ w_i]: genform's default and its
    /// departure from the paper.
    #[default]
    Bounded,
    /// `−Σ w_i e_i`, in (−∞, 0]: the paper's weighted sum of the criteria
    /// (negated, since genform maximises).
    Paper,
}

impl<'de> Deserialize<'de> for SurfaceForm {
    /// A form by name; another name is an error that lists the forms.
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        SurfaceForm::from_name(&name).ok_or_else(|| {
            serde::de::Error::custom(format!(
                "`{name}` is not a surface fitness form; the forms are `bounded` (Σ w/(1+e), the default) and \
                 `paper` (−Σ w·e, the paper's weighted sum)"
            ))
        })
    }
}

impl SurfaceForm {
    /// Both forms, the default first.
    pub const ALL: [SurfaceForm; 2] = [SurfaceForm::Bounded, SurfaceForm::Paper];

    /// The name in scene files: `bounded` or `paper`.
    pub fn name(self) -> &'static str {
        match self {
            SurfaceForm::Bounded => "bounded",
            SurfaceForm::Paper => "paper",
        }
    }

    /// The form named `name` (see [`SurfaceForm::name`]).
    pub fn from_name(name: &str) -> Option<SurfaceForm> {
        SurfaceForm::ALL.into_iter().find(|f| f.name() == name)
    }

    /// What one criterion adds to the fitness, in words for plot titles:
    /// `w/(1+e)` or `−w·e`.
    pub fn contribution_formula(self) -> &'static str {
        match self {
            SurfaceForm::Bounded => "w/(1+e)",
            SurfaceForm::Paper => "−w·e",
        }
    }

    /// Whether this is the default (`bounded`), which scene files and
    /// logs leave unwritten.
    pub fn is_bounded(&self) -> bool {
        *self == SurfaceForm::Bounded
    }

    /// The contribution of a criterion with weight `w` and error `e`
    /// (`e` may be +∞: `0` bounded, `−∞` paper).
    pub fn contribution(self, w: f64, e: f64) -> f64 {
        match self {
            SurfaceForm::Bounded => w / (1.0 + e),
            // 0 − w·e, not −(w·e): a criterion on target adds +0, not −0.
            SurfaceForm::Paper => 0.0 - w * e,
        }
    }
}

impl Default for SurfaceGoal {
    /// Weight 0: the criterion is skipped.
    fn default() -> Self {
        SurfaceGoal { target: 0.0, weight: 0.0, floor: None }
    }
}

impl SurfaceGoal {
    /// A goal with the default floor.
    pub fn new(target: f64, weight: f64) -> SurfaceGoal {
        SurfaceGoal { target, weight, floor: None }
    }
}

/// The settings of a [`SurfaceScorer`]: one [`SurfaceGoal`] per criterion and
/// the form that combines them, the `[surface]` table of a scene config.
/// Keys are the criteria's [`SurfaceCriterion::name`]s and `form`; unknown
/// keys are rejected; criteria left out are skipped.
#[derive(Clone, Copy, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct SurfaceObjective {
    /// How the errors combine (`form = "bounded"`, the default, or
    /// `"paper"`); an unknown name is an error that lists both.
    #[serde(skip_serializing_if = "SurfaceForm::is_bounded")]
    pub form: SurfaceForm,
    /// x-extent + y-extent.
    pub size: SurfaceGoal,
    /// Σ over edges |Δz|.
    pub smoothness: SurfaceGoal,
    /// Vertices on the wrong side of soft boundaries (a count).
    pub soft_boundary: SurfaceGoal,
    /// Vertices / edges.
    pub subdivisions: SurfaceGoal,
    /// (sym(x) + sym(y)) / 2.
    pub symmetry: SurfaceGoal,
    /// z-extent.
    pub undulation: SurfaceGoal,
}

impl SurfaceObjective {
    /// The goal of `criterion`.
    pub fn goal(&self, criterion: SurfaceCriterion) -> &SurfaceGoal {
        match criterion {
            SurfaceCriterion::Size => &self.size,
            SurfaceCriterion::Smoothness => &self.smoothness,
            SurfaceCriterion::SoftBoundary => &self.soft_boundary,
            SurfaceCriterion::Subdivisions => &self.subdivisions,
            SurfaceCriterion::Symmetry => &self.symmetry,
            SurfaceCriterion::Undulation => &self.undulation,
        }
    }

    /// The goal of `criterion`, to change.
    pub fn goal_mut(&mut self, criterion: SurfaceCriterion) -> &mut SurfaceGoal {
        match criterion {
            SurfaceCriterion::Size => &mut self.size,
            SurfaceCriterion::Smoothness => &mut self.smoothness,
            SurfaceCriterion::SoftBoundary => &mut self.soft_boundary,
            SurfaceCriterion::Subdivisions => &mut self.subdivisions,
            SurfaceCriterion::Symmetry => &mut self.symmetry,
            SurfaceCriterion::Undulation => &mut self.undulation,
        }
    }

    /// This objective with `criterion` aiming at `target` with `weight`
    /// (default floor).
    pub fn with(mut self, criterion: SurfaceCriterion, target: f64, weight: f64) -> SurfaceObjective {
        *self.goal_mut(criterion) = SurfaceGoal::new(target, weight);
        self
    }
}

/// Why a [`SurfaceObjective`] cannot be scored with.
#[derive(thiserror::Error, Debug, Clone, PartialEq)]
pub enum SurfaceError {
    /// Every weight is 0, so every surface would score the same.
    #[error(
        "the surface objective has no criterion with a weight above 0; give at least one, \
         e.g. `size = {{ target = 10, weight = 1 }}`"
    )]
    NoCriteria,
    /// A target is NaN or infinite.
    #[error("surface criterion `{criterion}`: the target must be a finite number, not {target}")]
    BadTarget {
        /// The criterion's name.
        criterion: &'static str,
        /// The target given.
        target: f64,
    },
    /// A weight is negative, NaN or infinite.
    #[error(
        "surface criterion `{criterion}`: the weight must be a number from 0 to 1e9 (weights are relative), not {weight}"
    )]
    BadWeight {
        /// The criterion's name.
        criterion: &'static str,
        /// The weight given.
        weight: f64,
    },
    /// A floor is not a finite number above 0.
    #[error("surface criterion `{criterion}`: the floor must be finite and above 0, not {floor}")]
    BadFloor {
        /// The criterion's name.
        criterion: &'static str,
        /// The floor given.
        floor: f64,
    },
}

/// One criterion's part of a [`SurfaceScore`], for logs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceComponent {
    /// Which criterion.
    pub criterion: SurfaceCriterion,
    /// The raw measure `F_i`.
    pub measure: f64,
    /// The target `T_i`.
    pub target: f64,
    /// The weight `w_i`.
    pub weight: f64,
    /// `e_i = |F_i − T_i| / max(|T_i|, ε_i)`; +∞ when the measure is not finite.
    pub error: f64,
    /// What the criterion adds to the fitness: `w_i / (1 + e_i)` in the
    /// bounded form, `−w_i e_i` in the paper form.
    pub contribution: f64,
}

impl SurfaceComponent {
    /// The criterion's name.
    pub fn name(&self) -> &'static str {
        self.criterion.name()
    }
}

/// A scored surface: the fitness and every weighted criterion's part.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceScore {
    fitness: f64,
    len: usize,
    items: [SurfaceComponent; 6],
}

impl SurfaceScore {
    /// The sum of the components' contributions: `Σ w_i / (1 + e_i)` in
    /// [0, [`SurfaceScorer::best`]] (bounded form) or `−Σ w_i e_i` ≤ 0
    /// (paper form).
    pub fn fitness(&self) -> f64 {
        self.fitness
    }

    /// The criteria with weight > 0, in [`SurfaceCriterion::ALL`] order.
    pub fn components(&self) -> &[SurfaceComponent] {
        &self.items[..self.len]
    }
}

impl fmt::Display for SurfaceScore {
    /// `fitness F: size 10.1 (target 10, error 0.0125, +0.988), …` (the
    /// last number is the contribution, with its sign).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "fitness {:.6}:", self.fitness)?;
        for (i, c) in self.components().iter().enumerate() {
            let sep = if i == 0 { " " } else { ", " };
            write!(
                f,
                "{sep}{} {:.6} (target {}, error {:.6}, {:+.6})",
                c.name(),
                c.measure,
                c.target,
                c.error,
                c.contribution
            )?;
        }
        Ok(())
    }
}

/// A weighted criterion, checked.
#[derive(Clone, Copy, Debug)]
struct Active {
    criterion: SurfaceCriterion,
    target: f64,
    weight: f64,
    /// `max(|T|, ε)`.
    scale: f64,
}

/// Scores Scenes' surfaces against a [`SurfaceObjective`] (the module docs
/// give the formula). Immutable and shared between threads; it needs no
/// scratch.
#[derive(Clone, Debug)]
pub struct SurfaceScorer {
    objective: SurfaceObjective,
    active: Vec<Active>,
    best: f64,
}

impl SurfaceScorer {
    /// A scorer for `objective`: targets finite, weights finite and ≥ 0 with
    /// at least one above 0, floors finite and > 0; either form.
    pub fn new(objective: SurfaceObjective) -> Result<SurfaceScorer, SurfaceError> {
        let mut active = Vec::new();
        for criterion in SurfaceCriterion::ALL {
            let g = objective.goal(criterion);
            let name = criterion.name();
            if !g.target.is_finite() {
                return Err(SurfaceError::BadTarget { criterion: name, target: g.target });
            }
            if !(0.0..=MAX_WEIGHT).contains(&g.weight) {
                return Err(SurfaceError::BadWeight { criterion: name, weight: g.weight });
            }
            let floor = g.floor.unwrap_or_else(|| criterion.default_floor());
            if !(floor.is_finite() && floor > 0.0) {
                return Err(SurfaceError::BadFloor { criterion: name, floor });
            }
            if g.weight > 0.0 {
                active.push(Active { criterion, target: g.target, weight: g.weight, scale: g.target.abs().max(floor) });
            }
        }
        if active.is_empty() {
            return Err(SurfaceError::NoCriteria);
        }
        let best = match objective.form {
            SurfaceForm::Bounded => active.iter().map(|a| a.weight).sum(),
            SurfaceForm::Paper => 0.0,
        };
        Ok(SurfaceScorer { objective, active, best })
    }

    /// The settings.
    pub fn objective(&self) -> &SurfaceObjective {
        &self.objective
    }

    /// The fitness of a surface that meets every target: `Σ w_i` (bounded
    /// form) or 0 (paper form).
    pub fn best(&self) -> f64 {
        self.best
    }

    /// Scores measures already taken.
    pub fn score(&self, m: &SurfaceMeasures) -> SurfaceScore {
        let blank = SurfaceComponent {
            criterion: SurfaceCriterion::Size,
            measure: 0.0,
            target: 0.0,
            weight: 0.0,
            error: 0.0,
            contribution: 0.0,
        };
        let mut items = [blank; 6];
        let mut fitness = 0.0;
        for (item, a) in items.iter_mut().zip(&self.active) {
            let measure = m.get(a.criterion);
            let error = (measure - a.target).abs() / a.scale;
            // A non-finite measure (broken geometry) is as far off as can be.
            let error = if error.is_finite() { error } else { f64::INFINITY };
            let contribution = self.objective.form.contribution(a.weight, error);
            fitness += contribution;
            *item = SurfaceComponent {
                criterion: a.criterion,
                measure,
                target: a.target,
                weight: a.weight,
                error,
                contribution,
            };
        }
        SurfaceScore { fitness, len: self.active.len(), items }
    }

    /// Measures `scene`'s surfaces and scores them.
    pub fn score_scene(&self, scene: &Scene) -> SurfaceScore {
        self.score(&SurfaceMeasures::of(scene))
    }

    /// The fitness of `scene` (see [`SurfaceScore::fitness`]).
    pub fn fitness(&self, scene: &Scene) -> f64 {
        self.score_scene(scene).fitness()
    }
}
