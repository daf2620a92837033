//! Results at an output time.

/// Heat balance since the start of the run (transient, J per metre of
/// out-of-plane thickness) or of the steady state (rates, W/m, with
/// `stored_change = 0`).
///
/// `residual = stored_change − (convection_in + flux_in + prescribed_in)`.
/// Each inflow is integrated with the step's θ (`T_θ = θTⁿ⁺¹ + (1−θ)Tⁿ`),
/// consistently with the discrete equations, so the residual is round-off
/// when the solves are accurate and conduction and interface exchange
/// conserve heat.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct HeatBalance {
    /// Change of stored heat `Σ_i w_i (T_i − T_i⁰)`, `w = C·1`.
    pub stored_change: f64,
    /// Heat gained through convective edges (negative: lost).
    pub convection_in: f64,
    /// Heat gained through prescribed-flux edges.
    pub flux_in: f64,
    /// Heat supplied at prescribed-temperature nodes (the reactions).
    pub prescribed_in: f64,
    /// `stored_change − (convection_in + flux_in + prescribed_in)`.
    pub residual: f64,
    /// Gross heat moved, the scale of [`HeatBalance::relative_residual`]:
    /// the larger of the gross stored change `Σ_i |w_i (T_i − T_i⁰)|` and the
    /// gross boundary exchange `∫ Σ_i |inflow at node i| dt` (so that heat
    /// entering on one side and leaving on another, or redistributed inside
    /// an insulated body, does not make the scale vanish).
    pub scale: f64,
}

impl HeatBalance {
    /// `|residual| / scale` (`|residual|` when nothing moved at all).
    pub fn relative_residual(&self) -> f64 {
        if self.scale == 0.0 {
            self.residual.abs()
        } else {
            self.residual.abs() / self.scale
        }
    }

    pub(crate) fn close(mut self) -> Self {
        self.residual =
            self.stored_change - (self.convection_in + self.flux_in + self.prescribed_in);
        self
    }
}

/// Heat balance of one body (a connected part of the mesh), including the
/// heat it receives through interfaces. Same units and θ-consistency as
/// [`HeatBalance`].
#[derive(Debug, Clone, PartialEq)]
pub struct BodyBalance {
    /// Body name (its regions joined by `+`).
    pub body: String,
    /// Change of heat stored in the body.
    pub stored_change: f64,
    /// Heat gained through its convective edges.
    pub convection_in: f64,
    /// Heat gained through its prescribed-flux edges.
    pub flux_in: f64,
    /// Heat supplied at its prescribed-temperature nodes.
    pub prescribed_in: f64,
    /// Heat gained across interfaces (from the other bodies).
    pub interface_in: f64,
    /// `stored_change − (convection_in + flux_in + prescribed_in + interface_in)`.
    pub residual: f64,
    /// Gross heat moved in or out of the body (scale of the relative residual).
    pub scale: f64,
}

impl BodyBalance {
    /// `|residual| / scale` (`|residual|` when nothing moved).
    pub fn relative_residual(&self) -> f64 {
        if self.scale == 0.0 {
            self.residual.abs()
        } else {
            self.residual.abs() / self.scale
        }
    }
}

/// Heat exchange of one thermal interface element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InterfaceFlux {
    /// Temperature jump `⟦T⟧ = T_top − T_bottom` at the two integration
    /// points (P2 elements: at the two corner node pairs (1, 4) and (2, 3)).
    pub jump: [f64; 2],
    /// Flux `q = h_c ⟦T⟧` (W/m²) at the same two places: heat flowing from
    /// the top body into the bottom body per unit area.
    pub flux: [f64; 2],
    /// P2 elements only: `[⟦T⟧, q]` at the mid node pair (5, 6).
    pub mid: Option<[f64; 2]>,
    /// `∫ q dζ` over the element (W/m), top → bottom.
    pub heat_rate: f64,
}

/// Heat exchange across one named interface.
#[derive(Debug, Clone, PartialEq)]
pub struct InterfaceResult {
    /// Interface name.
    pub name: String,
    /// Per element, in the mesh's order.
    pub elements: Vec<InterfaceFlux>,
    /// Total heat rate across the interface (W/m), top → bottom.
    pub heat_rate: f64,
}

/// The thermal state at one output time.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    /// Time (s); 0 for a steady solution.
    pub time: f64,
    /// Number of time steps taken to reach it (0 for steady).
    pub step: usize,
    /// Nodal temperatures.
    pub temperature: Vec<f64>,
    /// Per-element mean temperature: `(T₁ + T₂ + T₃)/3` on linear triangles
    /// (the value their thermal strain `α (T_e − T_ref,e)` uses), `∫T dA / A`
    /// on 6-node triangles (whose thermal strain interpolates the nodal
    /// field instead).
    pub element_temperature: Vec<f64>,
    /// Per-element gradient ∇T (K/m) (6-node triangles: at the centroid).
    pub gradient: Vec<[f64; 2]>,
    /// Per-element heat flux `q = −k ∇T` (W/m²).
    pub flux: Vec<[f64; 2]>,
    /// Interface heat exchange, one entry per thermally coupled interface.
    pub interfaces: Vec<InterfaceResult>,
    /// Heat balance since the start (or steady rates).
    pub balance: HeatBalance,
    /// Heat balance of each body, in the mesh's body order.
    pub bodies: Vec<BodyBalance>,
}
