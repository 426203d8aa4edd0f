//! One point of the work-precision sweep: what the sweep (mod.rs) makes and runs and the truth
//! (truth.rs) measures, in a module of its own so that neither imports the other.

use crate::report::stability::Runner;
use crate::scene::Scene;

/// One point of the sweep.
#[derive(Clone, Debug)]
pub struct Setting {
    pub scene_name: &'static str,
    /// The series it belongs to (what is varied).
    pub method: &'static str,
    /// The value varied, for people.
    pub label: String,
    pub runner: Runner,
    pub scene: Scene,
}
