//! Initial temperature: per region, per node, and the rule for nodes on a
//! region border.

/// How a node shared by elements of regions with different initial
/// temperatures is initialised.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum BorderRule {
    /// The capacity-weighted mean of the adjacent elements' initial
    /// temperatures, `T_i = Σ_e ρc_e A_e T_e / Σ_e ρc_e A_e` (sums over the
    /// elements touching node i). This is the lumped L² projection of the
    /// piecewise-constant initial field: with the lumped capacity it keeps
    /// the initial heat content `Σ_e ρc_e A_e T_e` exactly. The default.
    #[default]
    CapacityWeighted,
    /// The highest adjacent initial temperature (the hot region owns its
    /// border, e.g. the weld's edge starts at weld temperature).
    Maximum,
    /// The lowest adjacent initial temperature.
    Minimum,
}

/// The initial-temperature specification of a model.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct InitialTemperature {
    /// Temperature of regions not listed in `regions`.
    pub default: Option<f64>,
    /// Per-region temperatures (region name, value).
    pub regions: Vec<(String, f64)>,
    /// Per-node overrides (node id, value), applied after the border rule.
    pub nodes: Vec<(usize, f64)>,
    /// Rule for nodes on a border between regions.
    pub border: BorderRule,
}
