//! Typed errors of `tecon-thermal`: every user mistake gets an error that
//! names what is wrong and where, never a panic or a garbage answer.
//!
//! Reference: issue 3 ("Errors") and STYLE.md convention 5.
//! Goal: each error variant a user can reach is produced, with the names.
//! Meshes: `rectangle` (region `domain`, edge sets left/right/bottom/top)
//! and two concentric rings `a`, `b` joined by interface `a_b`.

use tecon_mesh::{Mesh, RingLayer, layered_annulus, rectangle};
use tecon_thermal::{EdgeBc, Material, ThermalError, ThermalModel, ThetaScheme, TimeSchedule};

fn square() -> Mesh {
    rectangle(0.0, 0.0, 1.0, 1.0, 4, 4).unwrap()
}

fn rings() -> Mesh {
    layered_annulus(
        &[
            RingLayer {
                name: "a".into(),
                r_in: 1.0,
                r_out: 1.5,
                rows: 2,
            },
            RingLayer {
                name: "b".into(),
                r_in: 1.5,
                r_out: 2.0,
                rows: 2,
            },
        ],
        0.0,
        std::f64::consts::TAU,
        16,
    )
    .unwrap()
}

#[test]
fn non_positive_material_properties_are_rejected_with_the_region() {
    let mesh = square();
    for (m, property) in [
        (Material::new(0.0, 1.0, 1.0), "conductivity k"),
        (Material::new(-1.0, 1.0, 1.0), "conductivity k"),
        (Material::new(1.0, 0.0, 1.0), "density ρ"),
        (Material::new(1.0, 1.0, -434.0), "specific heat c"),
        (Material::new(1.0, f64::NAN, 1.0), "density ρ"),
    ] {
        let mut model = ThermalModel::new(&mesh);
        let err = model.set_material("domain", m).unwrap_err();
        match &err {
            ThermalError::InvalidMaterial {
                region,
                property: p,
                ..
            } => {
                assert_eq!(region, "domain");
                assert_eq!(*p, property);
            }
            other => panic!("unexpected {other:?}"),
        }
        assert!(err.to_string().contains("'domain'"), "{err}");
    }
    // Unknown region: the mesh's error, listing the regions.
    let mut model = ThermalModel::new(&mesh);
    let err = model
        .set_material("weld", Material::vessel_steel())
        .unwrap_err();
    assert!(matches!(err, ThermalError::Mesh(_)), "{err:?}");
    assert!(err.to_string().contains("weld"), "{err}");
    // A region without material.
    let mesh = rings();
    let mut model = ThermalModel::new(&mesh);
    model.set_material("a", Material::vessel_steel()).unwrap();
    model.set_interface_conductance("a_b", 850.0).unwrap();
    assert_eq!(
        model.assemble().unwrap_err(),
        ThermalError::MissingMaterial { region: "b".into() }
    );
}

#[test]
fn non_positive_film_coefficient_and_conductance_are_rejected() {
    let mesh = rings();
    let mut model = ThermalModel::new(&mesh);
    for h in [0.0, -10.25, f64::INFINITY] {
        let err = model
            .add_edge_bc("outer", EdgeBc::convection(h, 21.0))
            .unwrap_err();
        match err {
            ThermalError::InvalidBoundary { set, what, .. } => {
                assert_eq!(set, "outer");
                assert_eq!(what, "film coefficient h");
            }
            other => panic!("unexpected {other:?}"),
        }
    }
    assert!(matches!(
        model.add_edge_bc("outer", EdgeBc::convection(10.0, f64::NAN)),
        Err(ThermalError::InvalidBoundary { .. })
    ));
    assert!(matches!(
        model.add_edge_bc("nowhere", EdgeBc::flux(1.0)),
        Err(ThermalError::Mesh(_))
    ));
    for hc in [0.0, -850.0, f64::NAN] {
        let err = model.set_interface_conductance("a_b", hc).unwrap_err();
        match &err {
            ThermalError::InvalidConductance { interface, .. } => assert_eq!(interface, "a_b"),
            other => panic!("unexpected {other:?}"),
        }
        assert!(err.to_string().contains("a_b"));
    }
    assert!(tecon_thermal::ConstantConductance::new(0.0).is_err());
}

#[test]
fn a_law_returning_a_negative_conductance_is_caught_with_the_element() {
    #[derive(Debug)]
    struct Bad;
    impl tecon_thermal::ConductanceLaw for Bad {
        fn conductance(&self, s: &tecon_thermal::InterfacePointState) -> f64 {
            if s.pressure > 1.0 { -1.0 } else { 1.0 }
        }
    }
    let mesh = rings();
    let mut model = ThermalModel::new(&mesh);
    model
        .set_material_everywhere(Material::vessel_steel())
        .unwrap();
    model
        .set_interface_law("a_b", Bad, tecon_thermal::InterfaceQuadrature::Nodal)
        .unwrap();
    let n = mesh.interface("a_b").unwrap().elements.len();
    let mut states = vec![[tecon_thermal::InterfacePointState::default(); 2]; n];
    states[5][1].pressure = 2.0;
    model.set_interface_state("a_b", states).unwrap();
    assert_eq!(
        model.assemble().unwrap_err(),
        ThermalError::InvalidConductance {
            interface: "a_b".into(),
            element: Some(5),
            requirement: "non-negative and finite",
            value: -1.0
        }
    );
    assert!(matches!(
        model.set_interface_state("a_b", vec![]),
        Err(ThermalError::InterfaceStateLength { expected, got: 0, .. }) if expected == n
    ));
}

#[test]
fn an_interface_without_a_law_is_named() {
    let mesh = rings();
    let mut model = ThermalModel::new(&mesh);
    model
        .set_material_everywhere(Material::vessel_steel())
        .unwrap();
    assert_eq!(
        model.assemble().unwrap_err(),
        ThermalError::MissingInterfaceLaw {
            interface: "a_b".into()
        }
    );
}

#[test]
fn singular_steady_problems_name_the_free_body() {
    // One body, all edges adiabatic.
    let mesh = square();
    let mut model = ThermalModel::new(&mesh);
    model
        .set_material_everywhere(Material::vessel_steel())
        .unwrap();
    model.add_edge_bc("left", EdgeBc::flux(100.0)).unwrap();
    match model.solve_steady().unwrap_err() {
        ThermalError::SingularSteady {
            bodies,
            description,
        } => {
            assert_eq!(bodies, vec!["domain".to_string()]);
            assert!(description.contains("domain"));
        }
        other => panic!("unexpected {other:?}"),
    }
    // Two rings: convection outside only, interface adiabatic: ring `a`
    // floats; with a conducting interface the pair is anchored.
    let mesh = rings();
    let mut model = ThermalModel::new(&mesh);
    model
        .set_material_everywhere(Material::vessel_steel())
        .unwrap()
        .add_edge_bc("outer", EdgeBc::convection(10.0, 21.0))
        .unwrap()
        .set_interface_adiabatic("a_b")
        .unwrap();
    let err = model.solve_steady().unwrap_err();
    match &err {
        ThermalError::SingularSteady { bodies, .. } => assert_eq!(bodies, &vec!["a".to_string()]),
        other => panic!("unexpected {other:?}"),
    }
    assert!(err.to_string().contains("'a'"), "{err}");
    model.set_interface_conductance("a_b", 850.0).unwrap();
    let s = model.solve_steady().unwrap();
    assert!(s.temperature.iter().all(|t| (t - 21.0).abs() < 1e-9));
    // Neither ring anchored: both named together.
    let mut model = ThermalModel::new(&mesh);
    model
        .set_material_everywhere(Material::vessel_steel())
        .unwrap()
        .set_interface_conductance("a_b", 850.0)
        .unwrap();
    match model.solve_steady().unwrap_err() {
        ThermalError::SingularSteady { mut bodies, .. } => {
            bodies.sort();
            assert_eq!(bodies, vec!["a".to_string(), "b".to_string()]);
        }
        other => panic!("unexpected {other:?}"),
    }
}

#[test]
fn schedules_that_do_not_advance_are_rejected() {
    let bad = |r: Result<TimeSchedule, ThermalError>| {
        assert!(
            matches!(r, Err(ThermalError::ScheduleDoesNotAdvance { .. })),
            "{r:?}"
        )
    };
    bad(TimeSchedule::from_steps(vec![]));
    bad(TimeSchedule::from_steps(vec![1.0, 0.0, 1.0]));
    bad(TimeSchedule::from_steps(vec![1.0, -1.0]));
    bad(TimeSchedule::from_steps(vec![f64::NAN]));
    bad(TimeSchedule::uniform(0.0, 10));
    bad(TimeSchedule::uniform(1.0, 0));
    bad(TimeSchedule::segments(&[(10.0, 1.0), (5.0, 1.0)]));
    bad(TimeSchedule::segments(&[(10.0, 0.0)]));
    bad(TimeSchedule::geometric(0.0, 1.5, 3, 10.0));
    bad(TimeSchedule::geometric(1.0, 0.5, 3, 10.0));
    // A step too small to change t (1e-30 at t = 1e6).
    bad(TimeSchedule::from_steps_at(1e6, vec![1e-30]));
    let err = TimeSchedule::from_steps(vec![1.0, 0.0]).unwrap_err();
    assert!(err.to_string().contains("step 1"), "{err}");
    // The stepper refuses too.
    let mesh = square();
    let mut model = ThermalModel::new(&mesh);
    model
        .set_material_everywhere(Material::vessel_steel())
        .unwrap()
        .set_initial_default(21.0)
        .unwrap();
    let system = model.assemble().unwrap();
    let mut st = system.stepper(vec![21.0; mesh.n_nodes()], 0.0).unwrap();
    assert!(matches!(
        st.step(0.0, 1.0),
        Err(ThermalError::ScheduleDoesNotAdvance { .. })
    ));
    assert!(matches!(
        st.step(1.0, 0.3),
        Err(ThermalError::InvalidTheta { .. })
    ));
    assert!(ThetaScheme::new(0.4, 0).is_err());
    // Output times outside the schedule.
    let sch = TimeSchedule::uniform(1.0, 3).unwrap();
    assert!(matches!(
        model.solve_transient_collect(&sch, ThetaScheme::backward_euler(), &[4.0]),
        Err(ThermalError::OutputTimeOutOfRange { .. })
    ));
}

#[test]
fn initial_and_prescribed_temperature_mistakes_are_named() {
    let mesh = rings();
    let mut model = ThermalModel::new(&mesh);
    model
        .set_material_everywhere(Material::vessel_steel())
        .unwrap()
        .set_interface_conductance("a_b", 850.0)
        .unwrap()
        .set_initial_region("a", 100.0)
        .unwrap();
    let sch = TimeSchedule::uniform(1.0, 2).unwrap();
    assert_eq!(
        model
            .solve_transient_collect(&sch, ThetaScheme::backward_euler(), &[])
            .unwrap_err(),
        ThermalError::MissingInitialTemperature { region: "b".into() }
    );
    assert!(matches!(
        model.set_initial_region("b", f64::NAN),
        Err(ThermalError::InvalidInitialTemperature { .. })
    ));
    assert!(matches!(
        model.set_initial_node(100_000, 1.0),
        Err(ThermalError::NodeOutOfRange { .. })
    ));
    let mut bare = ThermalModel::new(&mesh);
    bare.set_material_everywhere(Material::vessel_steel())
        .unwrap()
        .set_interface_conductance("a_b", 850.0)
        .unwrap();
    assert_eq!(
        bare.solve_transient_collect(&sch, ThetaScheme::backward_euler(), &[])
            .unwrap_err(),
        ThermalError::NoInitialTemperature
    );
    // Two sets prescribing different temperatures at shared nodes.
    let mesh = square();
    let mut model = ThermalModel::new(&mesh);
    model
        .set_material_everywhere(Material::vessel_steel())
        .unwrap()
        .add_edge_bc("left", EdgeBc::temperature(10.0))
        .unwrap()
        .add_edge_bc("bottom", EdgeBc::temperature(20.0))
        .unwrap();
    match model.assemble().unwrap_err() {
        ThermalError::ConflictingTemperature {
            first_set,
            second_set,
            node,
            ..
        } => {
            assert_eq!(
                (first_set.as_str(), second_set.as_str()),
                ("left", "bottom")
            );
            assert_eq!(node, 0);
        }
        other => panic!("unexpected {other:?}"),
    }
}
