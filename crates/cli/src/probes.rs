//! Probe points of a case file checked against the mesh: a point outside
//! the domain is an error naming it, never silently snapped to the nearest
//! node.
//!
//! A point is inside when it lies in a triangle or within a quarter of that
//! triangle's size h = √(2 A) of it: points on a curved boundary between two
//! nodes lie outside the chords by the sagitta h²/(8 R), which this absorbs.

use tecon_mesh::Mesh;

/// Distance from `p` to the triangle (a, b, c): 0 inside, else to the nearest edge.
pub fn distance_to_triangle(p: [f64; 2], a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    let cross = |o: [f64; 2], u: [f64; 2], v: [f64; 2]| {
        (u[0] - o[0]) * (v[1] - o[1]) - (u[1] - o[1]) * (v[0] - o[0])
    };
    let (d1, d2, d3) = (cross(a, b, p), cross(b, c, p), cross(c, a, p));
    let neg = d1 < 0.0 || d2 < 0.0 || d3 < 0.0;
    let pos = d1 > 0.0 || d2 > 0.0 || d3 > 0.0;
    if !(neg && pos) {
        return 0.0;
    }
    let seg = |u: [f64; 2], v: [f64; 2]| {
        let (dx, dy) = (v[0] - u[0], v[1] - u[1]);
        let l2 = dx * dx + dy * dy;
        let t = if l2 > 0.0 {
            (((p[0] - u[0]) * dx + (p[1] - u[1]) * dy) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (p[0] - u[0] - t * dx).hypot(p[1] - u[1] - t * dy)
    };
    seg(a, b).min(seg(b, c)).min(seg(c, a))
}

/// `Ok` when `p` lies in the mesh (see the module note); otherwise the
/// distance to the nearest triangle and that triangle's size.
pub fn locate(mesh: &Mesh, p: [f64; 2]) -> Result<usize, (f64, f64)> {
    let x = mesh.nodes();
    let mut best = (f64::INFINITY, 0.0, 0usize);
    for (e, t) in mesh.triangles().iter().enumerate() {
        let (a, b, c) = (x[t[0]], x[t[1]], x[t[2]]);
        let d = distance_to_triangle(p, a, b, c);
        let area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).abs();
        let h = (2.0 * area).sqrt();
        if d <= 0.25 * h {
            return Ok(e);
        }
        if d < best.0 {
            best = (d, h, e);
        }
    }
    Err((best.0, best.1))
}

/// Checks every probe point; the error names the key, the point and how far
/// outside the mesh it lies.
pub fn check_inside(mesh: &Mesh, points: &[[f64; 2]], key: &str) -> Result<(), String> {
    for (i, &p) in points.iter().enumerate() {
        if !(p[0].is_finite() && p[1].is_finite()) {
            return Err(format!("{key}[{i}]: ({}, {}) is not a point", p[0], p[1]));
        }
        if let Err((d, h)) = locate(mesh, p) {
            return Err(format!(
                "{key}[{i}]: the point ({}, {}) lies outside the mesh ({d:.3e} m from the nearest element, whose size is {h:.3e} m)",
                p[0], p[1]
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    //! Goal: inside, on the boundary and just outside a curved boundary are
    //! accepted; a point clearly outside is named.
    use super::*;

    #[test]
    fn distance_to_a_triangle() {
        let (a, b, c) = ([0.0, 0.0], [1.0, 0.0], [0.0, 1.0]);
        assert_eq!(distance_to_triangle([0.2, 0.2], a, b, c), 0.0);
        assert_eq!(distance_to_triangle([0.5, 0.0], a, b, c), 0.0);
        assert!((distance_to_triangle([0.5, -0.5], a, b, c) - 0.5).abs() < 1e-15);
        assert!((distance_to_triangle([2.0, 0.0], a, b, c) - 1.0).abs() < 1e-15);
        assert!((distance_to_triangle([1.0, 1.0], a, b, c) - 0.5f64.sqrt()).abs() < 1e-15);
    }

    #[test]
    fn probes_outside_the_vessel_are_named() {
        let mesh = tecon_mesh::vessel_mesh(
            &tecon_mesh::VesselGeometry::default(),
            &tecon_mesh::VesselMeshSpec::paper(),
        )
        .unwrap();
        // inner radius 0.762 m, outer 0.7811 m; the half ring y ≥ 0
        let r = 0.77;
        let on_arc = |deg: f64| [r * deg.to_radians().cos(), r * deg.to_radians().sin()];
        check_inside(
            &mesh,
            &[on_arc(0.0), on_arc(37.3), on_arc(179.0)],
            "output.probes",
        )
        .unwrap();
        // on the inner circle between two nodes: outside the chord by the sagitta only
        let ri = 0.762;
        let t = 93.7f64.to_radians();
        check_inside(&mesh, &[[ri * t.cos(), ri * t.sin()]], "output.probes").unwrap();
        let e = check_inside(&mesh, &[on_arc(10.0), [0.0, 0.0]], "output.probes").unwrap_err();
        assert!(
            e.starts_with("output.probes[1]: the point (0, 0) lies outside the mesh"),
            "{e}"
        );
        let e = check_inside(&mesh, &[[0.77, -0.01]], "output.probes").unwrap_err();
        assert!(e.contains("(0.77, -0.01)"), "{e}");
    }
}
