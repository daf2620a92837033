//! `ThermalModel::reassemble`: after a change of the interface states only,
//! the interfaces alone are re-assembled onto the stored bulk K, and the
//! system equals a full assembly bit for bit (P1 and P2); after any other
//! change it is a full assembly.

use tecon_mesh::{Mesh, RingLayer, layered_annulus_of_order};
use tecon_thermal::{
    ConductanceLaw, EdgeBc, InterfacePointState, InterfaceQuadrature, Material, ThermalModel,
    ThermalSystem,
};

/// h_c = 100 + 4e-3 p + 1e-3 / (g + 1e-4): pressure and gap both matter.
#[derive(Debug)]
struct StateLaw;

impl ConductanceLaw for StateLaw {
    fn conductance(&self, s: &InterfacePointState) -> f64 {
        100.0 + 4e-3 * s.pressure.max(0.0) + 1e-3 / (s.gap.max(0.0) + 1e-4)
    }
}

fn rings(order: usize) -> Mesh {
    let layer = |name: &str, r_in, r_out| RingLayer {
        name: name.into(),
        r_in,
        r_out,
        rows: 2,
    };
    layered_annulus_of_order(
        &[layer("a", 1.0, 1.5), layer("b", 1.5, 2.0)],
        0.0,
        0.5 * std::f64::consts::PI,
        12,
        order,
    )
    .unwrap()
}

fn model(mesh: &Mesh) -> ThermalModel<'_> {
    let mut m = ThermalModel::new(mesh);
    m.set_material("a", Material::new(40.0, 7800.0, 480.0))
        .unwrap()
        .set_material("b", Material::new(20.0, 7800.0, 480.0))
        .unwrap()
        .add_edge_bc("inner", EdgeBc::temperature(300.0))
        .unwrap()
        .add_edge_bc("outer", EdgeBc::convection(50.0, 20.0))
        .unwrap()
        .set_interface_law("a_b", StateLaw, InterfaceQuadrature::Nodal)
        .unwrap()
        .set_initial_default(20.0)
        .unwrap();
    m
}

/// States that vary along the interface: some points open (gap > 0), some
/// pressed.
fn states(mesh: &Mesh, shift: f64) -> Vec<[InterfacePointState; 2]> {
    let n = mesh.interface("a_b").unwrap().elements.len();
    (0..n)
        .map(|e| {
            [0, 1].map(|k| {
                let x = (e * 2 + k) as f64 + shift;
                InterfacePointState {
                    gap: (1e-5 * (x * 0.7).sin()).max(0.0),
                    pressure: 1e5 * (1.0 + (x * 0.3).cos()),
                    temperature: 50.0 + x,
                }
            })
        })
        .collect()
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

fn assert_same(a: &ThermalSystem<'_>, b: &ThermalSystem<'_>) {
    assert_eq!(
        bits(a.conductivity_matrix().values()),
        bits(b.conductivity_matrix().values())
    );
    assert_eq!(
        bits(a.capacity_matrix().values()),
        bits(b.capacity_matrix().values())
    );
    assert_eq!(bits(a.load()), bits(b.load()));
    // and the same transient, heat balance included
    let run = |s: &ThermalSystem<'_>| {
        let mut st = s
            .stepper(s.initial_temperature().unwrap().to_vec(), 0.0)
            .unwrap();
        for _ in 0..3 {
            st.step(0.5, 0.5).unwrap();
        }
        (st.temperature().to_vec(), st.balance().relative_residual())
    };
    let (ta, ra) = run(a);
    let (tb, rb) = run(b);
    assert_eq!(bits(&ta), bits(&tb));
    assert_eq!(ra.to_bits(), rb.to_bits());
}

#[test]
fn new_interface_states_reassemble_to_the_full_assembly_bit_for_bit() {
    for order in [1, 2] {
        let mesh = rings(order);
        let mut m = model(&mesh);
        m.set_interface_state("a_b", states(&mesh, 0.0)).unwrap();
        let first = || m.assemble().unwrap();
        let before = bits(first().conductivity_matrix().values());
        let mut m2 = m.clone();
        m2.set_interface_state("a_b", states(&mesh, 3.7)).unwrap();
        let full = m2.assemble().unwrap();
        // the conductances did change
        assert_ne!(
            before,
            bits(full.conductivity_matrix().values()),
            "order {order}"
        );
        assert_same(&m2.reassemble(first()).unwrap(), &full);
        // from a clone of the model too (the coupling loop clones it)
        assert_same(&m2.clone().reassemble(first()).unwrap(), &full);
    }
}

#[test]
fn any_other_change_gives_a_full_assembly() {
    let mesh = rings(2);
    // interface states set: the first system keeps its bulk K, so only the
    // model's revision can tell that it is stale
    let mut m = model(&mesh);
    m.set_interface_state("a_b", states(&mesh, 0.0)).unwrap();
    let first = m.assemble().unwrap();
    let before = bits(first.conductivity_matrix().values());
    // a second convection condition on the outer edge changes the bulk K
    m.add_edge_bc("outer", EdgeBc::convection(30.0, 20.0))
        .unwrap();
    let full = m.assemble().unwrap();
    assert_ne!(before, bits(full.conductivity_matrix().values()));
    assert_same(&m.reassemble(first).unwrap(), &full);
    // a system of another model of the same mesh (other capacity, same
    // interface states) is not reused either
    let mut other = model(&mesh);
    other
        .set_capacity(tecon_thermal::CapacityKind::Lumped)
        .set_interface_state("a_b", states(&mesh, 0.0))
        .unwrap();
    assert_same(&m.reassemble(other.assemble().unwrap()).unwrap(), &full);
}

#[test]
fn a_bad_conductance_is_named_on_reassembly_too() {
    #[derive(Debug)]
    struct Negative;
    impl ConductanceLaw for Negative {
        fn conductance(&self, s: &InterfacePointState) -> f64 {
            if s.pressure > 1.0 { -1.0 } else { 10.0 }
        }
    }
    let mesh = rings(1);
    let mut m = model(&mesh);
    m.set_interface_law("a_b", Negative, InterfaceQuadrature::Nodal)
        .unwrap();
    let first = m.assemble().unwrap();
    m.set_interface_state("a_b", states(&mesh, 0.0)).unwrap();
    let e = m.reassemble(first).unwrap_err().to_string();
    assert!(e.contains("a_b") && e.contains("element 0"), "{e}");
}
