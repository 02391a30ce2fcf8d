//! Recompiling an L-system with other values of its ranged constants
//! (`ranged.rs`): what a genome's root gene sets in a generator.

use crate::compile::{self, LSystem};
use crate::ranged::RangedConstant;
use genform_core::diag::{Diagnostic, Severity};
use std::sync::Arc;

impl LSystem {
    /// The constants whose values are genes, in file order.
    pub fn ranged_constants(&self) -> &[RangedConstant] {
        &self.ranged
    }

    /// The system with its ranged constants set to `values` (one per
    /// [`ranged_constants`](Self::ranged_constants), in order; integer
    /// ones rounded), or why not (a value outside its range, or a formula
    /// that fails with these values).
    pub fn with_constants(&self, values: &[f64]) -> Result<LSystem, String> {
        if values.len() != self.ranged.len() {
            return Err(format!("expected {} constant values, got {}", self.ranged.len(), values.len()));
        }
        let admitted = self.ranged.iter().zip(values).map(|(c, &v)| c.admit(v)).collect::<Result<Vec<f64>, _>>()?;
        let Some(recipe) = &self.recipe else {
            return Ok(self.clone());
        };
        let with = |errors: Vec<Diagnostic>| {
            let shown: Vec<String> =
                self.ranged.iter().zip(&admitted).map(|(c, v)| format!("{} = {v}", c.name)).collect();
            let first = errors.into_iter().find(|d| d.severity == Severity::Error);
            let message = first.map_or_else(String::new, |d| {
                let at = d.span.and_then(|s| self.location(s)).map(|l| format!("{l}: ")).unwrap_or_default();
                format!(": {at}{}", d.message)
            });
            format!("the L-system does not compile with {}{message}", shown.join(", "))
        };
        let (mut fresh, _) =
            compile::compile_with(&recipe.file, compile::Meshes::Reuse(&recipe.surfaces), Some(&admitted))
                .map_err(with)?;
        // What the file's reader changed after compiling (an L-Py file's
        // module commands and name, an empty axiom) is not in the syntax,
        // so it comes from this system.
        fresh.alphabet.clone_from(&self.alphabet);
        fresh.settings.name.clone_from(&self.settings.name);
        fresh.source.clone_from(&self.source);
        if self.axiom.syms.is_empty() {
            fresh.axiom = self.axiom.clone();
        }
        fresh.ranged.clone_from(&self.ranged);
        fresh.recipe = Some(Arc::clone(recipe));
        Ok(fresh)
    }
}

#[cfg(test)]
mod tests {
    use crate::compile::{LSystem, compile_text};
    use crate::generator::LsGenerator;
    use genform_core::graph::Distribution;
    use genform_core::{Generator, Genome, Rng, Scene};
    use std::sync::Arc;

    /// A 2D tree whose angle, branch decay and trunk length are genes.
    const TREE: &str = "define n = 2 in 1..4\ndefine a = 30 in [10, 80]\ndefine len = 1 in [0.5, 2]\n\
        define decay = 0.7\nview: 2d\nangle: a\ngrowth: 0.9\nderivation: 3\naxiom: A(len)\nproduction:\n\
        A(x) -> F(x * n / 2)[+A(x * decay)][-A(x * decay)]\n";

    fn system(text: &str) -> LSystem {
        compile_text(text).unwrap_or_else(|e| panic!("{e:?}")).0
    }

    /// Every drawn point, for comparing drawings.
    fn points(g: &LsGenerator, genome: &Genome) -> Vec<[f32; 3]> {
        let mut scene = Scene::new();
        g.express(genome, &g.limits(), &mut scene).unwrap();
        scene.polylines.iter().flat_map(|l| l.points.iter().map(|p| p.to_array())).collect()
    }

    #[test]
    fn ranged_constants_read_their_written_value_and_are_listed() {
        let s = system(TREE);
        let names: Vec<(&str, bool, f64, f64, f64)> =
            s.ranged_constants().iter().map(|c| (c.name.as_str(), c.integer, c.value, c.min, c.max)).collect();
        assert_eq!(names, [("n", true, 2.0, 1.0, 4.0), ("a", false, 30.0, 10.0, 80.0), ("len", false, 1.0, 0.5, 2.0)]);
        assert_eq!(s.settings.angle, 30.0);
        let m = s.derive(1, &mut Rng::from_seed(0)).unwrap();
        assert_eq!(m.display(&s.alphabet, true), "F(1)[+A(0.7)][-A(0.7)]");
        // No ranged constant, nothing kept for recompiling.
        assert!(system("define k = 2\naxiom: A(k)\n").recipe.is_none());
    }

    #[test]
    fn with_constants_recompiles_every_reader_of_the_constants() {
        let s = system(TREE);
        let t = s.with_constants(&[3.4, 45.0, 2.0]).unwrap();
        // Rounded to a whole number; the setting `angle:` and the axiom follow.
        assert_eq!(t.settings.angle, 45.0);
        assert_eq!(t.axiom.display(&t.alphabet, true), "A(2)");
        let m = t.derive(1, &mut Rng::from_seed(0)).unwrap();
        assert_eq!(m.display(&t.alphabet, true), "F(3)[+A(1.4)][-A(1.4)]");
        let e = s.with_constants(&[2.0, 95.0, 1.0]).unwrap_err();
        assert!(e.contains("`a` = 95 is outside its range [10, 80]"), "{e}");
        assert!(s.with_constants(&[2.0, f64::NAN, 1.0]).is_err());
        assert!(s.with_constants(&[2.0]).is_err());
    }

    #[test]
    fn the_root_gene_holds_one_value_per_ranged_constant() {
        let g = LsGenerator::new(Arc::new(system(TREE))).unwrap();
        let root = g.graph().symbol(g.graph().root);
        let params: Vec<(&str, &Distribution)> =
            root.params.iter().map(|p| (p.name.as_str(), &p.components[0])).collect();
        assert_eq!(
            params,
            [
                ("n", &Distribution::IntRange { min: 1, max: 4 }),
                ("a", &Distribution::Uniform { min: 10.0, max: 80.0 }),
                ("len", &Distribution::Uniform { min: 0.5, max: 2.0 }),
            ]
        );
        // A system without ranged constants keeps a root without parameters.
        let plain = LsGenerator::new(Arc::new(system("axiom: A\nproduction:\nA -> F[+A][-A]\n"))).unwrap();
        assert!(plain.graph().symbol(0).params.is_empty());
    }

    #[test]
    fn genomes_carry_their_constants_into_the_drawing() {
        let g = LsGenerator::new(Arc::new(system(TREE))).unwrap();
        let limits = g.limits();
        let mut seen = Vec::new();
        for seed in 0..50 {
            let genome = g.sample(&mut Rng::from_seed(seed), &limits).unwrap().genome;
            let root = genome.root().unwrap();
            let v: Vec<f64> = genome.gene(root).params().collect();
            assert!((1.0..=4.0).contains(&v[0]) && v[0].fract() == 0.0, "{v:?}");
            assert!((10.0..=80.0).contains(&v[1]) && (0.5..=2.0).contains(&v[2]), "{v:?}");
            seen.push(v[0]);
            // Replays exactly.
            assert_eq!(points(&g, &genome), points(&g, &genome.clone()));
        }
        assert!([1.0, 2.0, 3.0, 4.0].iter().all(|n| seen.contains(n)), "the prior is uniform: {seen:?}");
        // The same derivation with another angle or length draws elsewhere.
        let genome = g.sample(&mut Rng::from_seed(1), &limits).unwrap().genome;
        let root = genome.root().unwrap();
        let before = points(&g, &genome);
        for values in [[2.0, 60.0, 1.0], [2.0, 30.0, 1.5]] {
            let mut other = genome.clone();
            other.set_params(root, &values);
            assert_ne!(points(&g, &other), before, "{values:?}");
        }
        // A value outside its range (a hand-edited genome) is refused.
        let mut bad = genome.clone();
        bad.set_params(root, &[9.0, 30.0, 1.0]);
        let e = g.express(&bad, &limits, &mut Scene::new()).unwrap_err();
        assert!(e.to_string().contains("`n` = 9 is outside its range 1..4"), "{e}");
    }
}
