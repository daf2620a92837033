//! The per-state interface table (`interface_NNN.csv`) of any mesh: one row
//! per interface point, in order along each interface.
//!
//! The solver reports joint points per element, so a node shared by two
//! interface elements (nodal integration) comes twice, once from each
//! element. Here coinciding points of one interface are merged (values
//! averaged, the status the more open or slipping one), and the points are
//! ordered by walking each chain of elements from an end (an open interface)
//! or from its lowest point (a closed one), with the arc length `s` from
//! there. The chain is found from the elements' own point order, so this
//! holds for any curve, not only circles around the origin.

use std::collections::BTreeMap;

use tecon_contact::ContactStatus;
use tecon_elastic::InterfacePointResult;

use crate::writers::csv_line;

/// Header of the table.
pub const HEADER: &str = "interface,s_m,x_m,y_m,jump_t_m,jump_n_m,shear_Pa,contact_pressure_Pa,slip_m,status (0 open; 1 stick; 2 slip)";

/// One merged interface point.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// Interface index.
    pub interface: usize,
    /// Arc length from the start of its chain (m).
    pub s: f64,
    /// Position (m).
    pub position: [f64; 2],
    /// Tangential and normal jump (m).
    pub jump: [f64; 2],
    /// Shear traction (Pa).
    pub shear: f64,
    /// Contact pressure (Pa, compression positive).
    pub pressure: f64,
    /// Accumulated slip (m).
    pub slip: f64,
    /// 0 open, 1 stick, 2 slip.
    pub status: u8,
}

fn code(s: ContactStatus) -> u8 {
    match s {
        ContactStatus::Open => 0,
        ContactStatus::Stick => 1,
        ContactStatus::Slip => 2,
    }
}

/// Which of two statuses a merged point reports: open before slip before
/// stick (the one that tells more about the joint).
fn worse(a: u8, b: u8) -> u8 {
    let rank = |s: u8| match s {
        0 => 2,
        2 => 1,
        _ => 0,
    };
    if rank(b) > rank(a) { b } else { a }
}

/// The merged, ordered rows of `points` (all interfaces).
pub fn rows(points: &[InterfacePointResult]) -> Vec<Row> {
    let mut by_interface: BTreeMap<usize, Vec<&InterfacePointResult>> = BTreeMap::new();
    for p in points {
        by_interface.entry(p.interface).or_default().push(p);
    }
    let mut out = Vec::new();
    for (itf, pts) in by_interface {
        out.extend(interface_rows(itf, &pts));
    }
    out
}

fn interface_rows(itf: usize, pts: &[&InterfacePointResult]) -> Vec<Row> {
    let scale = pts
        .iter()
        .map(|p| p.position[0].abs().max(p.position[1].abs()))
        .fold(0.0f64, f64::max)
        .max(f64::MIN_POSITIVE);
    let tol = 1e-9 * scale;
    // merge coinciding points: sort by position, group neighbours
    let mut idx: Vec<usize> = (0..pts.len()).collect();
    idx.sort_by(|&a, &b| {
        let (pa, pb) = (pts[a].position, pts[b].position);
        pa[0]
            .total_cmp(&pb[0])
            .then(pa[1].total_cmp(&pb[1]))
            .then(a.cmp(&b))
    });
    let mut id_of = vec![usize::MAX; pts.len()];
    let mut merged: Vec<(Row, usize)> = Vec::new();
    for &i in &idx {
        let p = pts[i];
        let found = merged
            .iter()
            .enumerate()
            .rev()
            .take_while(|(_, (r, _))| p.position[0] - r.position[0] <= tol)
            .find(|(_, (r, _))| (r.position[1] - p.position[1]).abs() <= tol)
            .map(|(k, _)| k);
        let row = Row {
            interface: itf,
            s: 0.0,
            position: p.position,
            jump: p.jump,
            shear: p.traction[0],
            pressure: -p.traction[1],
            slip: p.slip,
            status: code(p.status),
        };
        match found {
            Some(k) => {
                let (r, n) = &mut merged[k];
                let w = *n as f64;
                let avg = |a: f64, b: f64| (a * w + b) / (w + 1.0);
                r.jump = [avg(r.jump[0], row.jump[0]), avg(r.jump[1], row.jump[1])];
                r.shear = avg(r.shear, row.shear);
                r.pressure = avg(r.pressure, row.pressure);
                r.slip = avg(r.slip, row.slip);
                r.status = worse(r.status, row.status);
                *n += 1;
                id_of[i] = k;
            }
            None => {
                id_of[i] = merged.len();
                merged.push((row, 1));
            }
        }
    }
    // links between consecutive points of each element
    let mut elements: BTreeMap<usize, Vec<(usize, usize)>> = BTreeMap::new();
    for (i, p) in pts.iter().enumerate() {
        elements
            .entry(p.element)
            .or_default()
            .push((p.point, id_of[i]));
    }
    let m = merged.len();
    let mut links: Vec<Vec<usize>> = vec![Vec::new(); m];
    for list in elements.values_mut() {
        list.sort_unstable();
        for w in list.windows(2) {
            let (a, b) = (w[0].1, w[1].1);
            if a != b && !links[a].contains(&b) {
                links[a].push(b);
                links[b].push(a);
            }
        }
    }
    // walk the chains: ends first (open interfaces), then closed loops from
    // their first point in position order
    let mut seen = vec![false; m];
    let mut order: Vec<(usize, f64)> = Vec::with_capacity(m);
    let starts: Vec<usize> = (0..m)
        .filter(|&k| links[k].len() <= 1)
        .chain(0..m)
        .collect();
    for start in starts {
        if seen[start] {
            continue;
        }
        let mut s = 0.0;
        let mut cur = start;
        seen[cur] = true;
        order.push((cur, s));
        // from a loop's start, go to the neighbour that comes first in
        // position order (deterministic)
        while let Some(&next) = links[cur].iter().filter(|&&k| !seen[k]).min() {
            let (a, b) = (merged[cur].0.position, merged[next].0.position);
            s += (b[0] - a[0]).hypot(b[1] - a[1]);
            seen[next] = true;
            order.push((next, s));
            cur = next;
        }
    }
    order
        .into_iter()
        .map(|(k, s)| Row {
            s,
            ..merged[k].0.clone()
        })
        .collect()
}

/// The table as CSV text, interfaces named by `names`.
pub fn csv(names: &[String], points: &[InterfacePointResult]) -> String {
    let mut s = String::from(HEADER);
    s.push('\n');
    for r in rows(points) {
        let name = names.get(r.interface).map_or("", String::as_str);
        s += &format!("{name},");
        s += &csv_line(&[
            r.s,
            r.position[0],
            r.position[1],
            r.jump[0],
            r.jump[1],
            r.shear,
            r.pressure,
            r.slip,
            f64::from(r.status),
        ]);
        s.push('\n');
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(
        element: usize,
        point: usize,
        x: [f64; 2],
        p: f64,
        status: ContactStatus,
    ) -> InterfacePointResult {
        InterfacePointResult {
            interface: 0,
            element,
            point,
            position: x,
            jump: [0.0, 0.0],
            traction: [0.0, -p],
            status,
            slip: 0.0,
            debonded: false,
        }
    }

    #[test]
    fn an_open_chain_listed_out_of_order_comes_out_merged_and_in_order() {
        use ContactStatus::*;
        // three elements along y = 0 from x = 0 to 3, listed 2, 0, 1; the
        // shared nodes x = 1, 2 appear twice
        let pts = vec![
            point(2, 0, [2.0, 0.0], 20.0, Stick),
            point(2, 1, [3.0, 0.0], 30.0, Stick),
            point(0, 0, [0.0, 0.0], 0.0, Open),
            point(0, 1, [1.0, 0.0], 10.0, Stick),
            point(1, 0, [1.0, 0.0], 12.0, Slip),
            point(1, 1, [2.0, 0.0], 22.0, Stick),
        ];
        let r = rows(&pts);
        let xs: Vec<f64> = r.iter().map(|r| r.position[0]).collect();
        assert_eq!(xs, vec![0.0, 1.0, 2.0, 3.0]);
        let s: Vec<f64> = r.iter().map(|r| r.s).collect();
        assert_eq!(s, vec![0.0, 1.0, 2.0, 3.0]);
        assert_eq!(r[1].pressure, 11.0);
        assert_eq!(r[2].pressure, 21.0);
        assert_eq!(r[1].status, 2, "slip reported over stick");
        assert_eq!(r[0].status, 0);
        // the header has as many fields as every row
        let text = csv(&["joint".into()], &pts);
        let n = HEADER.split(',').count();
        assert!(text.lines().all(|l| l.split(',').count() == n), "{text}");
    }

    #[test]
    fn a_closed_ring_is_walked_once_from_its_lowest_point() {
        use ContactStatus::*;
        let n = 12;
        let at = |k: usize| {
            let t = 2.0 * std::f64::consts::PI * (k % n) as f64 / n as f64;
            [t.cos(), t.sin()]
        };
        // elements listed backwards
        let pts: Vec<InterfacePointResult> = (0..n)
            .rev()
            .flat_map(|e| {
                [
                    point(e, 0, at(e), 1.0, Stick),
                    point(e, 1, at(e + 1), 1.0, Stick),
                ]
            })
            .collect();
        let r = rows(&pts);
        assert_eq!(r.len(), n);
        assert_eq!(r[0].position, at(n / 2), "lowest x first");
        let total = r.last().unwrap().s;
        let chord = 2.0 * (std::f64::consts::PI / n as f64).sin();
        assert!((total - (n - 1) as f64 * chord).abs() < 1e-12, "{total}");
        // every point once
        let mut xs: Vec<[f64; 2]> = r.iter().map(|r| r.position).collect();
        xs.dedup();
        assert_eq!(xs.len(), n);
    }
}
