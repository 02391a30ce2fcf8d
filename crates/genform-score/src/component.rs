//! What a fitness is made of, as reports read it: its named parts
//! ([`Component`]) and the measures behind them ([`Score`]). Apart from the
//! [`crate::Scorer`] contract so that fitness forms can name their parts
//! without importing the scorers.

/// One named part of a fitness.
#[derive(Clone, Debug, PartialEq)]
pub struct Component {
    /// Its name: a criterion (`size`) or a term (`good`, `length`).
    pub name: &'static str,
    /// The raw measure the term is made of.
    pub measure: f64,
    /// The value the measure should have, for criteria with a target.
    pub target: Option<f64>,
    /// Its weight.
    pub weight: f64,
    /// How far the measure is from its target, in the criterion's units of
    /// error (criteria with a target).
    pub error: Option<f64>,
    /// What it adds to the fitness (the components add up to it).
    pub value: f64,
    /// The most it can add.
    pub max: f64,
}

/// A scored model: the fitness, what it is made of and what was measured.
#[derive(Clone, Debug, PartialEq)]
pub struct Score {
    /// The fitness ([`crate::Scorer::fitness`] of the same model, bit for bit).
    pub fitness: f64,
    /// Its parts, in the scorer's order.
    pub components: Vec<Component>,
    /// The raw measures by name (a counting target's `good`, `bad`,
    /// `overlap`, `outside`, `target`; a criterion's measure).
    pub measures: Vec<(&'static str, f64)>,
}

impl Score {
    /// The measure called `name`.
    pub fn measure(&self, name: &str) -> Option<f64> {
        self.measures.iter().find(|(n, _)| *n == name).map(|(_, v)| *v)
    }
}
