//! `tecon torsion`: Saint-Venant torsion of a prismatic bar by the wavelet
//! boundary integral method (crate `tecon-wavelet-bem`).
//!
//! ```text
//! tecon torsion --section ellipse:a=2,b=1
//! tecon torsion --section rectangle:w=1,h=2 --n 512 --method nystrom --format json
//! tecon torsion --section limacon:a=1,c=0.5 --grading 4 --out out/cardioid
//! tecon torsion --section my_section.toml --study
//! tecon torsion --section tube:ro=1,ri=0.6 --tol 1e-10
//! ```
//!
//! By default the resolution is chosen by error control: a starting n from
//! the geometry, doubled until J and τ_max at n and n/2 agree to `--tol`.
//! An unconverged result is printed with `converged: false` and a warning,
//! and the command exits with status 2 unless `--allow-unconverged`.

use crate::plot::{ColouredPath, LinePlot, Series};
use serde_json::json;
use std::io::Write;
use std::path::PathBuf;
use tecon_wavelet_bem::control::default_max_n;
use tecon_wavelet_bem::daubechies::Daubechies;
use tecon_wavelet_bem::{
    LinearSolver, Method, Options, sections, solve, solve_to_tolerance, solve_with_estimate,
};

/// Discretisation method (CLI spelling).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum MethodArg {
    /// periodised Daubechies wavelet Galerkin (default)
    Daubechies,
    /// harmonic (Shannon) wavelet Galerkin, spectral
    Shannon,
    /// Kress Nyström, reference
    Nystrom,
}

/// Output format.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum FormatArg {
    /// human-readable
    Text,
    /// one JSON object
    Json,
}

/// Arguments of `tecon torsion`.
#[derive(clap::Args, Debug)]
pub struct TorsionArgs {
    /// Section: circle:r=R | ellipse:a=A,b=B | rectangle:w=W,h=H | triangle:a=A |
    /// polygon:x1,y1;x2,y2;... | regular:n=N,r=R | groove:a=A,b=B | limacon:a=A,c=C |
    /// tube:ro=RO,ri=RI | box:w=W,h=H,t=T (or tf=TF,tw=TW) | path to a TOML file
    #[arg(long)]
    pub section: String,
    /// Relative tolerance on J, τ_max, the shear centre and Γ (error control: n doubles until
    /// two resolutions agree)
    #[arg(long, default_value_t = 1e-8, allow_hyphen_values = true)]
    pub tol: f64,
    /// Largest n the error control may use [default: 4096 (dense solves: n = 4096 takes
    /// seconds); where a rotational symmetry folds the system to order n/k, up to 16 384
    /// with n/k within 4096 (up to 2^19 for a regular polygon graded at thousands of flat
    /// vertices, such as the 2000-gon)]
    #[arg(long)]
    pub max_n: Option<usize>,
    /// Print an unconverged result and exit 0 (it is still flagged `converged: false`)
    #[arg(long)]
    pub allow_unconverged: bool,
    /// Experts: fixed number of unknowns per boundary curve (daubechies: an even n, usually a
    /// power of two);
    /// the error estimate then comes from a second solve at n/2
    #[arg(long)]
    pub n: Option<usize>,
    /// Discretisation method
    #[arg(long, value_enum, default_value_t = MethodArg::Daubechies)]
    pub method: MethodArg,
    /// Daubechies wavelet dbN
    #[arg(long, default_value = "db4")]
    pub wavelet: String,
    /// Kress grading exponent at corners (default 8; 4 at a cusp)
    #[arg(long, allow_hyphen_values = true)]
    pub grading: Option<f64>,

    /// Kress's grading map on every panel: no corner zones on the long
    /// panels of thin-walled sections with re-entrant corners (a cross-check;
    /// the zones halve the n that thin walls need)
    #[arg(long)]
    pub no_corner_zones: bool,
    /// Solve the whole system even where the section has a rotational
    /// symmetry (by default a boundary that a turn by 2π/k maps onto itself
    /// is solved on one k-th of it: the same answer to rounding; this is the
    /// cross-check). A regular polygon with nearly flat vertices (a 2000-gon)
    /// is then parametrised by arc length, its vertices unresolved (flagged)
    #[arg(long)]
    pub no_symmetry: bool,
    /// Sections with re-entrant corners or inward cusps (where τ is infinite):
    /// the largest boundary shear stress at least R from every such point is
    /// reported with its estimated error [default R: A/P, half the mean wall
    /// thickness 2A/P]; when R is given, the refinement also follows it until
    /// it meets --tol
    #[arg(long, value_name = "R", allow_hyphen_values = true)]
    pub corner_distance: Option<f64>,
    /// Output format
    #[arg(long, value_enum, default_value_t = FormatArg::Text)]
    pub format: FormatArg,
    /// Directory for boundary.csv and the plots (|q| vs arc length, section coloured by |q|)
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Convergence study: solve at n/8, n/4, n/2, n and report the observed order
    #[arg(long)]
    pub study: bool,
    /// Removed (see docs/torsion.md): the thresholded matrix lost definiteness on polygons
    /// and was slower than the dense solve at every n the dense solve reaches
    #[arg(long, value_name = "EPS", hide = true)]
    pub compress: Option<f64>,
    /// Interior points "x1,y1;x2,y2;..." where u and the stresses are reported
    #[arg(long, allow_hyphen_values = true)]
    pub points: Option<String>,
}

type BoxErr = Box<dyn std::error::Error + Send + Sync>;

fn parse_points(s: &str) -> Result<Vec<[f64; 2]>, BoxErr> {
    let mut out = Vec::new();
    for (i, p) in s.split(';').filter(|p| !p.trim().is_empty()).enumerate() {
        let (x, y) = p
            .split_once(',')
            .ok_or_else(|| format!("--points: point {} `{p}` is not x,y", i + 1))?;
        let x: f64 = x
            .trim()
            .parse()
            .map_err(|_| format!("--points: point {}: bad x `{x}`", i + 1))?;
        let y: f64 = y
            .trim()
            .parse()
            .map_err(|_| format!("--points: point {}: bad y `{y}`", i + 1))?;
        out.push([x, y]);
    }
    Ok(out)
}

fn js(v: f64) -> serde_json::Value {
    if v.is_finite() {
        json!(v)
    } else {
        serde_json::Value::Null
    }
}

/// Runs `tecon torsion`: prints the report (text or JSON), writes the
/// files and, with `--out`, the text report as `report.txt`; returns the
/// warnings (also printed on stderr).
pub fn run(args: TorsionArgs) -> Result<Vec<String>, BoxErr> {
    let section = sections::parse_spec(&args.section)?;
    let method = match args.method {
        MethodArg::Daubechies => Method::Daubechies,
        MethodArg::Shannon => Method::Shannon,
        MethodArg::Nystrom => Method::Nystrom,
    };
    let wavelet = Daubechies::from_name(&args.wavelet).ok_or_else(|| {
        format!(
            "--wavelet: unknown wavelet `{}` (expected db1 … db20)",
            args.wavelet
        )
    })?;
    let cusp = section
        .curves()
        .iter()
        .flat_map(|c| c.junctions.iter())
        .any(|j| j.interior_angle > 1.9 * std::f64::consts::PI || j.interior_angle < 0.1);
    let grading = args.grading.unwrap_or(if cusp { 4.0 } else { 8.0 });
    if args.compress.is_some() {
        return Err(
            "--compress was removed: the thresholded wavelet matrix lost definiteness \
                    on polygons (CG breakdown) and was slower than the dense solve at every n \
                    the dense solve reaches; see docs/torsion.md"
                .into(),
        );
    }
    if let Some(r) = args.corner_distance
        && !(r > 0.0 && r.is_finite())
    {
        return Err(format!("--corner-distance: need a positive length, got {r}").into());
    }
    if !(args.tol > 0.0 && args.tol < 1.0) {
        return Err(format!("--tol: need 0 < TOL < 1, got {}", args.tol).into());
    }
    let opts = Options {
        n: args.n.unwrap_or(8),
        method,
        wavelet_order: wavelet.order,
        grading,
        linear: LinearSolver::Dense,
        corner_zones: !args.no_corner_zones,
        corner_distance: args.corner_distance,
        symmetry: !args.no_symmetry,
    };
    let points = match &args.points {
        Some(p) => parse_points(p)?,
        None => vec![],
    };
    // reject bad points before the (possibly long) solve
    for (i, &p) in points.iter().enumerate() {
        use tecon_wavelet_bem::geometry::PointLocation;
        let where_ = match section.locate(p) {
            PointLocation::Inside => continue,
            PointLocation::Outside => "outside",
            PointLocation::OnBoundary => "on the boundary of",
        };
        return Err(format!(
            "--points: point {} ({}, {}) is {where_} the section",
            i + 1,
            p[0],
            p[1]
        )
        .into());
    }
    let ctl = match args.n {
        Some(_) => solve_with_estimate(&section, &opts, args.tol)?,
        None => solve_to_tolerance(
            &section,
            &opts,
            args.tol,
            args.max_n.unwrap_or_else(|| default_max_n(&section, &opts)),
        )?,
    };
    let sol = &ctl.solution;
    let n = sol.options.n;
    let opts = sol.options;
    let ms = ctl.max_shear;
    let warp = &ctl.warping;
    let interior = sol.interior_checked(&points)?;
    // points so close to Γ that round-off exceeds the tolerance say so
    let mut warnings = ctl.warnings.clone();
    for (i, v) in interior.iter().enumerate() {
        if v.round_off > args.tol {
            warnings.push(format!(
                "point {} ({}, {}) is {:.1e} from the boundary: its stresses carry round-off of up to about {:.1e} of the section's stress scale (ε × size / distance), more than --tol {:.1e}",
                i + 1,
                v.x[0],
                v.x[1],
                v.distance,
                v.round_off,
                args.tol
            ));
        }
    }

    // convergence study
    let mut study = Vec::new();
    if args.study {
        let mut ns: Vec<usize> = (0..4).rev().map(|k| n >> k).filter(|&m| m >= 8).collect();
        if method == Method::Daubechies {
            ns.retain(|&m| m >= wavelet.min_n());
        }
        let mut js_: Vec<(usize, f64)> = Vec::new();
        for &m in &ns {
            let s = solve(&section, &Options { n: m, ..opts })?;
            js_.push((m, s.torsional_rigidity));
        }
        for k in 0..js_.len() {
            let order = if k >= 2 {
                let d1 = (js_[k - 1].1 - js_[k - 2].1).abs();
                let d2 = (js_[k].1 - js_[k - 1].1).abs();
                if d1 > 0.0 && d2 > 0.0 {
                    Some((d1 / d2).log2())
                } else {
                    None
                }
            } else {
                None
            };
            let diff = if k >= 1 {
                Some(js_[k].1 - js_[k - 1].1)
            } else {
                None
            };
            study.push((js_[k].0, js_[k].1, diff, order));
        }
    }

    // files
    const OUT_SAMPLES_MAX: usize = 1 << 16;
    let mut written = Vec::new();
    if let Some(dir) = &args.out {
        std::fs::create_dir_all(dir)
            .map_err(|e| format!("--out: cannot create `{}`: {e}", dir.display()))?;
        // 4 samples per node, at most 65 536 per curve (all that n ≤ 16 384
        // gives; the 2000-gon graded at n = 128 000 wrote 110 MB of report
        // and SVGs of 300 000 points in 32 s; 65 536 are 32 per edge)
        let m = (4 * n).clamp(1024, OUT_SAMPLES_MAX);
        let samples = sol.boundary_samples(m);
        let csv = dir.join("boundary.csv");
        let mut f = std::io::BufWriter::new(
            std::fs::File::create(&csv)
                .map_err(|e| format!("--out: cannot write `{}`: {e}", csv.display()))?,
        );
        writeln!(f, "t,s,x,y,q,tau,curve")?;
        // every curve: 0 the outer boundary, k ≥ 1 hole[k − 1] (arc length from each curve's start)
        let per_curve: Vec<_> = (0..sol.curve_count())
            .map(|k| {
                if k == 0 {
                    samples.clone()
                } else {
                    sol.boundary_samples_on(k, m)
                }
            })
            .collect();
        for (k, on_k) in per_curve.iter().enumerate() {
            for s in on_k {
                writeln!(
                    f,
                    "{:.16e},{:.16e},{:.16e},{:.16e},{:.16e},{:.16e},{k}",
                    s.t,
                    s.s,
                    s.x[0],
                    s.x[1],
                    s.q,
                    s.q.abs()
                )?;
            }
        }
        f.flush()?;
        written.push(csv);
        // the warping function ω_n (normalised, about the shear centre) on every curve
        let wcsv = dir.join("warping.csv");
        let mut f = std::io::BufWriter::new(
            std::fs::File::create(&wcsv)
                .map_err(|e| format!("--out: cannot write `{}`: {e}", wcsv.display()))?,
        );
        writeln!(f, "curve,t,x,y,omega")?;
        let wsamples = sol.warping_samples(warp, m);
        for s in &wsamples {
            writeln!(
                f,
                "{},{:.16e},{:.16e},{:.16e},{:.16e}",
                s.curve, s.t, s.x[0], s.x[1], s.omega
            )?;
        }
        f.flush()?;
        written.push(wcsv);
        // key results with their estimated errors (a short table in report.html)
        let rcsv = dir.join("results.csv");
        let mut f = std::io::BufWriter::new(
            std::fs::File::create(&rcsv)
                .map_err(|e| format!("--out: cannot write `{}`: {e}", rcsv.display()))?,
        );
        writeln!(f, "quantity,value,estimated_error,error_measure")?;
        writeln!(
            f,
            "J,{:.15e},{:.3e},relative",
            sol.torsional_rigidity, ctl.j_error
        )?;
        match ms.value {
            Some(t) => writeln!(
                f,
                "tau_max,{t:.15e},{:.3e},relative",
                ctl.tau_error.unwrap_or(f64::NAN)
            )?,
            None => {
                writeln!(f, "tau_max,inf,,singular")?;
                if let Some(a) = ms.away {
                    writeln!(
                        f,
                        "tau_away,{:.15e},{:.3e},relative (largest boundary value at least tau_away_distance from every singular point)",
                        a.value,
                        ctl.tau_error.unwrap_or(f64::NAN)
                    )?;
                    writeln!(f, "tau_away_distance,{:.15e},,length", a.distance)?;
                }
            }
        }
        for (k, name) in ["shear_centre_x", "shear_centre_y"].iter().enumerate() {
            writeln!(
                f,
                "{name},{:.15e},{:.3e},relative to the radius of gyration",
                warp.shear_centre[k], ctl.shear_centre_error
            )?;
        }
        writeln!(
            f,
            "warping_constant,{:.15e},{:.3e},relative",
            warp.warping_constant, ctl.warping_error
        )?;
        writeln!(f, "n,{n},,")?;
        writeln!(f, "converged,{},,", ctl.converged)?;
        f.flush()?;
        written.push(rcsv);
        // the figures draw every curve (the holes too) on one colour scale
        let wpath = |k: usize| -> Vec<(f64, f64, f64)> {
            wsamples
                .iter()
                .filter(|s| s.curve == k)
                .map(|s| (s.x[0], s.x[1], s.omega))
                .collect()
        };
        let cpw = ColouredPath {
            title: format!("{}: warping function ω_n on the boundary", section.name),
            value_label: "ω_n [length²]".into(),
            points: wpath(0),
            closed: true,
            more_closed: (1..sol.curve_count()).map(wpath).collect(),
        };
        let (a, b) = cpw.write_svg_png(&dir.join("section_warping"))?;
        written.push(a);
        written.push(b);
        let lp = LinePlot {
            title: format!("Boundary shear stress, {}", section.name),
            x_label: "arc length s [length]".into(),
            y_label: "τ/(Gθ) = |∂u/∂n| [length]".into(),
            // one series per curve; a single curve keeps its plain label
            series: per_curve
                .iter()
                .enumerate()
                .map(|(k, on_k)| Series {
                    label: match (per_curve.len(), k) {
                        (1, _) => format!("{} n={}", method, n),
                        (_, 0) => format!("outer boundary, {} n={}", method, n),
                        _ => format!("hole[{}], {} n={}", k - 1, method, n),
                    },
                    points: on_k.iter().map(|s| (s.s, s.q.abs())).collect(),
                })
                .collect(),
        };
        let (a, b) = lp.write_svg_png(&dir.join("boundary_shear"))?;
        written.push(a);
        written.push(b);
        let cp = ColouredPath {
            title: format!("{}: |q| on the boundary", section.name),
            value_label: "τ/(Gθ) [length]".into(),
            points: samples
                .iter()
                .map(|s| (s.x[0], s.x[1], s.q.abs()))
                .collect(),
            closed: true,
            more_closed: per_curve[1..]
                .iter()
                .map(|on_k| on_k.iter().map(|s| (s.x[0], s.x[1], s.q.abs())).collect())
                .collect(),
        };
        let (a, b) = cp.write_svg_png(&dir.join("section_shear"))?;
        written.push(a);
        written.push(b);
    }

    // the printed report, report.txt (written at the end of this run), and
    // the page report.html (built from the folder by the caller, `tecon
    // torsion` in main.rs, once this run returns Ok): both are written only
    // when the run succeeds, so they are listed only then
    if let Some(dir) = &args.out
        && (ctl.converged || args.allow_unconverged)
    {
        written.push(dir.join(crate::report_html::REPORT_TEXT));
        written.push(dir.join(crate::report_html::REPORT));
    }

    let method_name = method.to_string();
    // the printed report (also report.txt beside the outputs)
    let mut text = String::new();
    macro_rules! say {
        ($($a:tt)*) => {{
            text += &format!($($a)*);
            text.push('\n');
        }};
    }
    {
        say!("section            {}", section.name);
        for note in &section.notes {
            say!("note               {note}");
        }
        say!(
            "method             {method_name}{}  n = {n}  grading p = {grading}{}",
            if method == Method::Daubechies {
                format!(" (db{})", wavelet.order)
            } else {
                String::new()
            },
            match sol.zoned_panels() {
                0 => String::new(),
                z => format!(" (corner zones on {z} long panels)"),
            }
        );
        if sol.symmetry_order > 1 {
            say!(
                "symmetry           {k}-fold rotation: solved on 1/{k} of each boundary curve",
                k = sol.symmetry_order
            );
        }
        let pr = section.properties();
        say!("area               {:.15e}", section.area);
        say!(
            "centroid           ({:.12e}, {:.12e})",
            pr.centroid[0],
            pr.centroid[1]
        );
        say!(
            "second moments     I_xx = {:.12e}  I_yy = {:.12e}  I_xy = {:.12e} (about the centroid)",
            pr.ixx,
            pr.iyy,
            pr.ixy
        );
        say!(
            "principal axes     I_11 = {:.12e}  I_22 = {:.12e}  at φ = {:.6}° (I_11 axis from x)",
            pr.i11,
            pr.i22,
            pr.phi.to_degrees()
        );
        say!(
            "torsional rigidity J = {:.15e}   (T = G θ J)",
            sol.torsional_rigidity
        );
        match (ms.value, ms.at) {
            (Some(t), Some(at)) => say!(
                "max shear stress   τ_max/(Gθ) = {t:.15e} at ({:.10}, {:.10})",
                at[0],
                at[1]
            ),
            (_, at) => {
                let at = at.unwrap_or([f64::NAN, f64::NAN]);
                say!(
                    "max shear stress   singular (τ → ∞) at the re-entrant corner/cusp ({:.10}, {:.10})",
                    at[0],
                    at[1]
                );
                match ms.away {
                    Some(a) => {
                        say!(
                            "away from corners  τ/(Gθ) = {:.15e} at ({:.10}, {:.10}): the largest on the boundary at least R = {:.6e} from every singular point (--corner-distance)",
                            a.value,
                            a.at[0],
                            a.at[1],
                            a.distance
                        );
                        if a.distance > a.requested {
                            say!(
                                "                   (R raised from {:.6e}: closer to a singular point the boundary values are not resolved, whatever n; the graded corner cluster reaches {:.6e})",
                                a.requested,
                                a.distance
                            );
                        }
                    }
                    None => say!(
                        "away from corners  none: no boundary point lies R = {:.6e} or more from every singular point (--corner-distance)",
                        opts.corner_distance
                            .unwrap_or_else(|| section.default_corner_distance())
                    ),
                }
            }
        }
        say!(
            "shear centre       ({:.12e}, {:.12e})   (Trefftz; {:+.6e}, {:+.6e} from the centroid)",
            warp.shear_centre[0],
            warp.shear_centre[1],
            warp.shear_centre[0] - pr.centroid[0],
            warp.shear_centre[1] - pr.centroid[1]
        );
        say!(
            "warping constant   Γ = {:.12e}   (∫ ω_n² dA, ω_n normalised about the shear centre)",
            warp.warping_constant
        );
        for (k, h) in sol.holes.iter().enumerate() {
            say!(
                "{:<19}u = C = {:.15e} on its boundary (area {:.6e})",
                format!("hole[{k}]"),
                h.stress_function,
                section.holes[k].area
            );
        }
        say!(
            "multiplier c       {:.3e}   (0 for the exact solution; small c alone does not prove accuracy)",
            sol.multiplier
        );
        let tau_e = match (ms.singular, ctl.tau_error) {
            (false, Some(e)) => format!("τ_max {e:.1e}"),
            (true, Some(e)) => format!("τ away from the singular points {e:.1e}"),
            (_, None) => "τ_max - (singular)".into(),
        };
        // "n = 512 vs 256" (difference), "n = 512 vs 256, rate from 128" (extrapolated)
        let from = &ctl.estimated_from;
        let basis = match from.as_slice() {
            [older, coarse, fine] => format!("n = {fine} vs {coarse}, rate from {older}"),
            [coarse, fine] => format!("n = {fine} vs {coarse}"),
            _ => format!("n = {n}"),
        };
        say!(
            "estimated error    J {:.1e}, {tau_e}, shear centre {:.1e}, Γ {:.1e} (relative; tolerance {:.1e}; {basis})",
            ctl.j_error,
            ctl.shear_centre_error,
            ctl.warping_error,
            ctl.tol,
        );
        say!(
            "converged          {}",
            if ctl.converged { "yes" } else { "NO" }
        );
        // each point with its distance to Γ and the bound ε L/distance on
        // the round-off of its stresses (the JSON's `distance`, `round_off`)
        for v in &interior {
            say!(
                "point ({}, {}): u = {:.12e}  τ_xz = {:.12e}  τ_yz = {:.12e}  (distance {:.1e}, round-off ≤ {:.1e})",
                v.x[0],
                v.x[1],
                v.u,
                v.tau_xz,
                v.tau_yz,
                v.distance,
                v.round_off
            );
        }
        if !study.is_empty() {
            say!("study:      n   J                        J(n) − J(n/2)   observed order");
            for (m, j, d, o) in &study {
                say!(
                    "       {m:>6}   {j:.15e}   {}   {}",
                    d.map(|v| format!("{v:>12.3e}"))
                        .unwrap_or_else(|| format!("{:>12}", "-")),
                    o.map(|v| format!("{v:.2}")).unwrap_or_else(|| "-".into())
                );
            }
        }
        for p in &written {
            say!("wrote              {}", p.display());
        }
    }
    match args.format {
        FormatArg::Json => {
            let v = json!({
                "section": section.name,
                "notes": section.notes,
                "torsional_rigidity": sol.torsional_rigidity,
                "max_shear_stress": ms.value,
                "max_shear_stress_at": ms.at,
                "singular": ms.singular,
                "max_shear_stress_away": ms.away.map(|a| json!({
                    "value": a.value,
                    "at": a.at,
                    "distance": a.distance,
                    "requested_distance": a.requested,
                    "estimated_error": ctl.tau_error.map(js),
                })),
                "n": n,
                "method": method_name,
                "wavelet": if method == Method::Daubechies { Some(format!("db{}", wavelet.order)) } else { None },
                "grading": grading,
                "corner_zone_panels": sol.zoned_panels(),
                "symmetry_order": sol.symmetry_order,
                "multiplier": js(sol.multiplier),
                "converged": ctl.converged,
                "tolerance": ctl.tol,
                "estimated_error": {
                    "torsional_rigidity": js(ctl.j_error),
                    "max_shear_stress": if ms.singular { None } else { ctl.tau_error.map(js) },
                    "max_shear_stress_away": if ms.singular { ctl.tau_error.map(js) } else { None },
                    "shear_centre": js(ctl.shear_centre_error),
                    "warping_constant": js(ctl.warping_error),
                },
                "shear_centre": warp.shear_centre,
                "warping_constant": js(warp.warping_constant),
                "warping": {
                    "shear_centre": warp.shear_centre,
                    "warping_constant": js(warp.warping_constant),
                    "centroidal_warping_constant": js(warp.centroidal_constant),
                    "product_integrals_about_centroid": [js(warp.product_integrals[0]), js(warp.product_integrals[1])],
                    "omega": "normalised warping function about the shear centre, ∂ω/∂n = (y − y_S) n_x − (x − x_S) n_y, ∫ω dA = 0; boundary values in warping.csv with --out",
                },
                "levels": ctl.levels,
                "estimated_from": ctl.estimated_from,
                "warnings": warnings,
                "holes": sol.holes.iter().zip(&section.holes).map(|(h, g)| json!({
                    "stress_function": h.stress_function,
                    "area": g.area,
                    "centroid": g.centroid,
                })).collect::<Vec<_>>(),
                "area": section.area,
                "centroid": section.centroid,
                "polar_moment": section.polar_moment(),
                "properties": section.properties(),
                "interior": interior,
                "study": study.iter().map(|(m, j, d, o)| json!({"n": m, "torsional_rigidity": j, "difference": d, "observed_order": o})).collect::<Vec<_>>(),
                "files": written.iter().map(|p| p.display().to_string()).collect::<Vec<_>>(),
            });
            println!("{}", serde_json::to_string_pretty(&v)?);
        }
        FormatArg::Text => print!("{text}"),
    }
    for w in &warnings {
        eprintln!("warning: {w}");
        text += &format!("warning: {w}\n");
    }
    if !ctl.converged && !args.allow_unconverged {
        return Err(format!(
            "the result is not converged to --tol {:.1e} (see the warning); raise --max-n, \
             loosen --tol, or pass --allow-unconverged to accept it",
            ctl.tol
        )
        .into());
    }
    if let Some(dir) = &args.out {
        let path = dir.join(crate::report_html::REPORT_TEXT);
        std::fs::write(&path, &text).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    Ok(warnings)
}
