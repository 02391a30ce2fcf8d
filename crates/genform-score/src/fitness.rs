//! Turning what a scorer counted into one fitness value.
//!
//! Every scorer reduces a Scene to [`Counts`] (weighted voxel or pixel
//! sums); [`Fitness`] combines them with the genome length into the number
//! optimizers maximize. The forms are the ones of the ShapeGenetics paper,
//! its reference implementation and its thesis (reference §1.5), with
//! `S(a, b, x)` Perlin's smootherstep.

pub use genform_core::expr::smootherstep;

/// What a scorer measured on one Scene. Counts are weighted sums, so with
/// unit weights they are plain voxel or pixel counts.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Counts {
    /// Covered target: Σ over targets of fill weight × covered target cells.
    pub good: f64,
    /// Covered non-target: Σ over targets of avoid weight × covered cells
    /// outside that target (for images: the weight of covered negative pixels).
    pub bad: f64,
    /// Cells covered more than once (self-overlap).
    pub overlap: f64,
    /// Cells of the model that fall outside the grid or image.
    pub outside: f64,
    /// The most `good` can reach: Σ fill weight × target cells (`T`).
    pub target: f64,
}

impl std::ops::AddAssign for Counts {
    fn add_assign(&mut self, o: Counts) {
        self.good += o.good;
        self.bad += o.bad;
        self.overlap += o.overlap;
        self.outside += o.outside;
        self.target += o.target;
    }
}

/// How [`Counts`] and the genome length become a fitness.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Form {
    /// The paper's volume fitness:
    /// `g·S(0,T,good) − b·S(0,2T,bad+overlap+outside) − l·S(lo,hi,len)`.
    #[default]
    Paper,
    /// The reference's `separate_overlap` variant:
    /// `g·S(0,T,good) − b·S(0,3T,bad) − o·S(0,good+bad,overlap+outside) − l·S(lo,hi,len)`.
    SeparateOverlap,
    /// The reference's image fitness:
    /// `g·S(0,T,good) − b·S(0,T,bad+outside) − l·S(lo,hi,len)`.
    Image,
    /// The thesis' linear scores s_vol / s_img (§4.1, §4.2), normalized by
    /// `T` so weights keep their meaning across grid resolutions:
    /// `(g·good − b·(bad+outside) − o·overlap) / T − l·S(lo,hi,len)`.
    Linear,
    /// What the reference implementation's CPU volume evaluator
    /// (`GenericVolumeEvaluator.cpp`, the one behind its measured runs)
    /// computes: `g·S(0,T,good) − b·S(0,2T,missed+bad) − l·S(lo,hi,len)`
    /// with `missed = T − good`. A target cell the model misses costs as
    /// much as a model cell outside the target; overlap and cells outside
    /// the grid are not counted at all (that evaluator only sets voxels
    /// and skips those off the grid).
    ReferenceCpu,
}

impl Form {
    /// Every form with its configuration name.
    pub const NAMES: [(&'static str, Form); 5] = [
        ("paper", Form::Paper),
        ("separate-overlap", Form::SeparateOverlap),
        ("image", Form::Image),
        ("linear", Form::Linear),
        ("reference-cpu", Form::ReferenceCpu),
    ];

    /// The form named `name` (see [`Form::NAMES`]).
    pub fn from_name(name: &str) -> Option<Form> {
        Form::NAMES.iter().find(|(n, _)| *n == name).map(|&(_, f)| f)
    }

    /// This form's configuration name.
    pub fn name(self) -> &'static str {
        Form::NAMES.iter().find(|(_, f)| *f == self).map(|&(n, _)| n).unwrap_or("paper")
    }
}

/// The constants of a fitness function.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fitness {
    /// Which formula.
    pub form: Form,
    /// Weight of covered target (α, `g`).
    pub good: f64,
    /// Weight of covered non-target (β, `b`).
    pub bad: f64,
    /// Weight of self-overlap (`o`, the thesis' w_self).
    pub overlap: f64,
    /// Weight of the length term (γ, `l`).
    pub length: f64,
    /// Genome length at which the length penalty starts (`l_opt`).
    pub length_from: f64,
    /// Genome length at which the length penalty is full (`l_max`).
    pub length_to: f64,
}

impl Default for Fitness {
    /// The spaceship experiment's constants (reference §1.9).
    fn default() -> Self {
        Fitness {
            form: Form::Paper,
            good: 2.0,
            bad: 15.0,
            overlap: 1.0,
            length: 0.1,
            length_from: 4.0,
            length_to: 100.0,
        }
    }
}

impl Fitness {
    /// The fitness of a model with counts `c` and `len` genes. Larger is
    /// better; the maximum is `good` (all target covered, nothing else, no
    /// length penalty). An empty target (`T = 0`) scores 0 for coverage.
    pub fn eval(&self, c: &Counts, len: usize) -> f64 {
        let t = c.target;
        let s = |a: f64, b: f64, x: f64| if b > a { smootherstep(a, b, x) } else { 0.0 };
        let len_term = self.length * smootherstep(self.length_from, self.length_to, len as f64);
        let body = match self.form {
            Form::Paper => self.good * s(0.0, t, c.good) - self.bad * s(0.0, 2.0 * t, c.bad + c.overlap + c.outside),
            Form::SeparateOverlap => {
                self.good * s(0.0, t, c.good)
                    - self.bad * s(0.0, 3.0 * t, c.bad)
                    - self.overlap * s(0.0, c.good + c.bad, c.overlap + c.outside)
            }
            Form::Image => self.good * s(0.0, t, c.good) - self.bad * s(0.0, t, c.bad + c.outside),
            Form::ReferenceCpu => {
                let missed = (t - c.good).max(0.0);
                self.good * s(0.0, t, c.good) - self.bad * s(0.0, 2.0 * t, missed + c.bad)
            }
            Form::Linear => {
                if t > 0.0 {
                    (self.good * c.good - self.bad * (c.bad + c.outside) - self.overlap * c.overlap) / t
                } else {
                    0.0
                }
            }
        };
        body - len_term
    }

    /// The terms of [`Fitness::eval`] as named components (`good`, `bad`,
    /// `overlap`, `length`, as the form has them): what each adds, its
    /// weight, the measure it is made of and the most it can add. They add
    /// up to the fitness (to rounding, in the `linear` form).
    pub fn components(&self, c: &Counts, len: usize) -> Vec<crate::component::Component> {
        let t = c.target;
        let s = |a: f64, b: f64, x: f64| if b > a { smootherstep(a, b, x) } else { 0.0 };
        let term = |name: &'static str, measure: f64, weight: f64, value: f64, sign: f64| crate::component::Component {
            name,
            measure,
            target: None,
            weight,
            error: None,
            value,
            max: (sign * weight).max(0.0),
        };
        let mut out = match self.form {
            Form::Paper => {
                let wrong = c.bad + c.overlap + c.outside;
                vec![
                    term("good", c.good, self.good, self.good * s(0.0, t, c.good), 1.0),
                    term("bad", wrong, self.bad, -(self.bad * s(0.0, 2.0 * t, wrong)), -1.0),
                ]
            }
            Form::SeparateOverlap => {
                let wrong = c.overlap + c.outside;
                vec![
                    term("good", c.good, self.good, self.good * s(0.0, t, c.good), 1.0),
                    term("bad", c.bad, self.bad, -(self.bad * s(0.0, 3.0 * t, c.bad)), -1.0),
                    term("overlap", wrong, self.overlap, -(self.overlap * s(0.0, c.good + c.bad, wrong)), -1.0),
                ]
            }
            Form::Image => vec![
                term("good", c.good, self.good, self.good * s(0.0, t, c.good), 1.0),
                term("bad", c.bad + c.outside, self.bad, -(self.bad * s(0.0, t, c.bad + c.outside)), -1.0),
            ],
            Form::ReferenceCpu => {
                let wrong = (t - c.good).max(0.0) + c.bad;
                vec![
                    term("good", c.good, self.good, self.good * s(0.0, t, c.good), 1.0),
                    term("bad", wrong, self.bad, -(self.bad * s(0.0, 2.0 * t, wrong)), -1.0),
                ]
            }
            Form::Linear => {
                let per = |v: f64| if t > 0.0 { v / t } else { 0.0 };
                vec![
                    term("good", c.good, self.good, per(self.good * c.good), 1.0),
                    term("bad", c.bad + c.outside, self.bad, per(-(self.bad * (c.bad + c.outside))), -1.0),
                    term("overlap", c.overlap, self.overlap, per(-(self.overlap * c.overlap)), -1.0),
                ]
            }
        };
        let len_term = self.length * smootherstep(self.length_from, self.length_to, len as f64);
        out.push(term("length", len as f64, self.length, -len_term, -1.0));
        out
    }

    /// The best fitness a model of `len` genes can reach (everything
    /// covered, nothing wrong), for reporting results as a fraction.
    pub fn max_reachable(&self, len: usize) -> f64 {
        let c = Counts { good: 1.0, target: 1.0, ..Counts::default() };
        self.eval(&c, len)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-12
    }

    #[test]
    fn smootherstep_hand_values() {
        assert_eq!(smootherstep(0.0, 1.0, -1.0), 0.0);
        assert_eq!(smootherstep(0.0, 1.0, 2.0), 1.0);
        assert!(close(smootherstep(0.0, 1.0, 0.5), 0.5));
        // t = 0.25: t³(t(6t−15)+10) = 0.015625 · (0.25·(−13.5)+10) = 0.103515625
        assert!(close(smootherstep(0.0, 4.0, 1.0), 0.103515625));
    }

    #[test]
    fn paper_form_by_hand() {
        let f = Fitness { length: 0.0, ..Fitness::default() };
        // T = 100, good = 50 → 2·0.5; bad + overlap = 100 of 2T → 15·0.5.
        let c = Counts { good: 50.0, bad: 80.0, overlap: 15.0, outside: 5.0, target: 100.0 };
        assert!(close(f.eval(&c, 10), 2.0 * 0.5 - 15.0 * 0.5));
        let full = Counts { good: 100.0, target: 100.0, ..Counts::default() };
        assert!(close(f.eval(&full, 10), 2.0));
    }

    #[test]
    fn reference_cpu_form_counts_missed_target_as_bad_and_ignores_overlap() {
        let f = Fitness { form: Form::ReferenceCpu, length: 0.0, ..Fitness::default() };
        // T = 100, good = 50 → 2·S(0,100,50) = 1; missed 50 + extra 50 = 100
        // of 2T → 15·0.5. Overlap and out-of-grid cells change nothing.
        let c = Counts { good: 50.0, bad: 50.0, overlap: 40.0, outside: 9.0, target: 100.0 };
        assert!(close(f.eval(&c, 10), 2.0 * 0.5 - 15.0 * 0.5));
        // The paper form sees 99 bad cells less than half of 2T here.
        let paper = Fitness { form: Form::Paper, ..f };
        assert!(paper.eval(&c, 10) > f.eval(&c, 10));
        // An empty model misses everything: −15·S(0,2T,T) = −7.5.
        let empty = Counts { target: 100.0, ..Counts::default() };
        assert!(close(f.eval(&empty, 10), -7.5));
        let full = Counts { good: 100.0, overlap: 30.0, target: 100.0, ..Counts::default() };
        assert!(close(f.eval(&full, 10), 2.0));
        assert!(close(f.max_reachable(4), 2.0));
    }

    #[test]
    fn length_penalty_is_smootherstep_of_length() {
        let f = Fitness { good: 0.0, bad: 0.0, length: 0.1, length_from: 4.0, length_to: 100.0, ..Fitness::default() };
        let c = Counts { target: 1.0, ..Counts::default() };
        assert!(close(f.eval(&c, 4), 0.0));
        assert!(close(f.eval(&c, 52), -0.05));
        assert!(close(f.eval(&c, 500), -0.1));
    }

    #[test]
    fn separate_overlap_and_image_forms() {
        let c = Counts { good: 30.0, bad: 30.0, overlap: 12.0, outside: 0.0, target: 60.0 };
        let sep = Fitness {
            form: Form::SeparateOverlap,
            good: 1.0,
            bad: 1.0,
            overlap: 1.0,
            length: 0.0,
            ..Fitness::default()
        };
        // S(0,60,30)=0.5; S(0,180,30)=S(t=1/6); S(0,60,12)=S(t=0.2)
        let st = |t: f64| t * t * t * (t * (6.0 * t - 15.0) + 10.0);
        assert!(close(sep.eval(&c, 1), 0.5 - st(1.0 / 6.0) - st(0.2)));
        let img = Fitness { form: Form::Image, ..sep };
        assert!(close(img.eval(&c, 1), 0.5 - 0.5));
        let lin = Fitness { form: Form::Linear, ..sep };
        assert!(close(lin.eval(&c, 1), (30.0 - 30.0 - 12.0) / 60.0));
    }

    #[test]
    fn empty_target_does_not_divide_by_zero() {
        for (_, form) in Form::NAMES {
            let f = Fitness { form, ..Fitness::default() };
            assert!(f.eval(&Counts { bad: 5.0, ..Counts::default() }, 3).is_finite());
        }
    }

    #[test]
    fn names_round_trip() {
        for (n, f) in Form::NAMES {
            assert_eq!(Form::from_name(n), Some(f));
            assert_eq!(f.name(), n);
        }
    }
}
