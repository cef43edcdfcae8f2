//! What `tune` minimises: one number per scene from its counts (summed over the scene's views
//! and resolutions), and one for the suite from the scenes' numbers.

use serde::Serialize;
use shadowtruth::metrics::Counts;

/// The objective of one scene, from the rates of its scored pixels.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Objective {
    /// False shadow + false lit.
    Total,
    /// False shadow + weight · false lit.
    Weighted { weight: f64 },
    /// The least false lit with false shadow at most `max_false_shadow`. A setting above that
    /// bound scores 1 + its false shadow, worse than any setting within it.
    FalseLitUnder { max_false_shadow: f64 },
}

impl Objective {
    pub fn of(&self, counts: &Counts) -> f64 {
        let r = counts.rates();
        match *self {
            Objective::Total => r.false_shadow + r.false_lit,
            Objective::Weighted { weight } => r.false_shadow + weight * r.false_lit,
            Objective::FalseLitUnder { max_false_shadow } if r.false_shadow <= max_false_shadow => {
                r.false_lit
            }
            Objective::FalseLitUnder { .. } => 1.0 + r.false_shadow,
        }
    }

    /// Whether a setting with this objective meets the objective's constraint (always, but for
    /// `FalseLitUnder`, whose settings beyond the bound score above 1).
    pub fn feasible(&self, value: f64) -> bool {
        !matches!(self, Objective::FalseLitUnder { .. }) || value < 1.0
    }

    /// How the objective reads in a table or on an axis.
    pub fn describe(&self) -> String {
        match *self {
            Objective::Total => "false shadow + false lit".into(),
            Objective::Weighted { weight } => format!("false shadow + {weight}·false lit"),
            Objective::FalseLitUnder { max_false_shadow } => {
                format!("false lit, with false shadow ≤ {max_false_shadow}")
            }
        }
    }
}

/// How the scenes' objectives make the suite's.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, clap::ValueEnum)]
#[serde(rename_all = "snake_case")]
pub enum SuiteAggregate {
    /// The mean over scenes (each scene weighs the same, whatever its pixel count).
    #[default]
    Mean,
    /// The worst scene.
    Worst,
}

impl SuiteAggregate {
    pub fn of(&self, scene_values: &[f64]) -> f64 {
        match self {
            SuiteAggregate::Mean => scene_values.iter().sum::<f64>() / scene_values.len().max(1) as f64,
            SuiteAggregate::Worst => scene_values.iter().copied().fold(0.0, f64::max),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn counts(false_shadow: u64, false_lit: u64) -> Counts {
        Counts { evaluated: 1000, false_shadow, false_lit, ..Counts::default() }
    }

    #[test]
    fn each_objective_reads_the_rates_it_names() {
        let c = counts(30, 10);
        assert_eq!(Objective::Total.of(&c), 0.04);
        assert_eq!(Objective::Weighted { weight: 3.0 }.of(&c), 0.03 + 3.0 * 0.01);
        assert_eq!(Objective::FalseLitUnder { max_false_shadow: 0.03 }.of(&c), 0.01);
        assert_eq!(Objective::FalseLitUnder { max_false_shadow: 0.02 }.of(&c), 1.03);
        assert!(!Objective::FalseLitUnder { max_false_shadow: 0.02 }.feasible(1.03));
        assert!(Objective::FalseLitUnder { max_false_shadow: 0.03 }.feasible(0.01));
        assert!(Objective::Total.feasible(1.5));
        // Any setting within the bound beats any setting beyond it.
        assert!(Objective::FalseLitUnder { max_false_shadow: 0.02 }.of(&counts(0, 1000)) < 1.03);
    }

    #[test]
    fn the_suite_is_the_mean_or_the_worst_scene() {
        assert_eq!(SuiteAggregate::Mean.of(&[0.1, 0.3]), 0.2);
        assert_eq!(SuiteAggregate::Worst.of(&[0.1, 0.3]), 0.3);
    }
}
