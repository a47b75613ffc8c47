//! `fpc-lab timing`: in-process median solve times for the standard cases
//! (default actuator, N = 8, tip-only output), how the tip-loaded solve
//! scales with N, the time to a tip within 0.01 mm of the N -> infinity
//! limit, and (with `--peer DIR`) the same cases of an external peer run
//! alternately with ours.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::Context as _;
use fpc::finger::Solver;
use fpc::plan::{PartitionKind, Refinement};
use fpc::{
    Actuator, Coefficients, Finger, Load, ModelId, Plan, PlannedFinger, Solution, SolveOptions,
    Solved,
};
use serde::Serialize;

/// Flags of `fpc-lab timing`. Numeric flags take `allow_hyphen_values` (see
/// the `fpc` binary's `finger` flags): `-1` or `-inf` is a value for the parser to reject.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Print one JSON object instead of tables.
    #[arg(long)]
    json: bool,
    /// Wall-clock budget per measured case, in milliseconds.
    #[arg(long, default_value_t = 400, allow_hyphen_values = true)]
    budget_ms: u64,
    /// A built performance peer (a directory holding `driver`, as
    /// `benches/peer/build_peer.py` leaves it): run it and our cold and
    /// warm cases alternately and print the ratios.
    #[arg(long, value_name = "DIR")]
    peer: Option<PathBuf>,
    /// Alternating rounds against the peer.
    #[arg(long, default_value_t = 5, allow_hyphen_values = true)]
    peer_rounds: u32,
}

/// The tip load of the standard loaded case (N, finger frame).
const FX: f64 = 0.939782;
const FZ: f64 = 0.521707;

/// The element counts of the scaling table.
const SCALING_ELEMENTS: [usize; 4] = [8, 32, 128, 256];

/// The tolerance of the `to_0p01mm` entry (mm).
const TIP_TOLERANCE_MM: f64 = 0.01;

fn tip_load() -> Load {
    Load::unloaded().with_tip_force(FX, FZ)
}

fn tip_only() -> SolveOptions {
    SolveOptions::default().tip_only()
}

/// Median wall time (us) of `f` over runs until `budget` is spent (at
/// least 11 runs), and the number of runs. The first call warms caches.
fn median_us<T>(
    budget: Duration,
    mut f: impl FnMut() -> anyhow::Result<T>,
) -> anyhow::Result<(f64, usize, T)> {
    let mut last = f()?;
    let mut samples = Vec::new();
    let start = Instant::now();
    while (start.elapsed() < budget || samples.len() < 11) && samples.len() < 200_000 {
        let t = Instant::now();
        last = f()?;
        samples.push(t.elapsed().as_secs_f64() * 1e6);
    }
    samples.sort_by(f64::total_cmp);
    Ok((samples[samples.len() / 2], samples.len(), last))
}

/// Rounds of [`paired`] measurements.
const PAIRED_ROUNDS: usize = 7;

/// `a` and `b` timed alternately in [`PAIRED_ROUNDS`] rounds (each side a
/// median over `budget / rounds`), and the median over the rounds of b's
/// median over a's in the same round. On a shared machine a solve's time
/// shifts between slow and fast phases that last seconds; two medians taken
/// at different times carry that shift, a ratio within one round far less.
fn paired_ratio<A, B>(
    budget: Duration,
    mut a: impl FnMut() -> anyhow::Result<A>,
    mut b: impl FnMut() -> anyhow::Result<B>,
) -> anyhow::Result<f64> {
    let each = budget / (2 * PAIRED_ROUNDS as u32);
    let mut ratios = Vec::with_capacity(PAIRED_ROUNDS);
    for _ in 0..PAIRED_ROUNDS {
        let (ta, _, _) = median_us(each, &mut a)?;
        let (tb, _, _) = median_us(each, &mut b)?;
        ratios.push(tb / ta);
    }
    Ok(median(&ratios))
}

/// One standard case.
#[derive(Serialize)]
struct Case {
    #[serde(skip)]
    name: &'static str,
    median_us: f64,
    runs: usize,
    iterations: usize,
    residual: f64,
    coupled: bool,
    #[serde(skip)]
    tip: [f64; 2],
}

/// Where a timed solve starts.
#[derive(Clone, Copy)]
enum Start<'a> {
    /// Nothing given: the solve computes its own start.
    Scratch,
    /// The scene's rest state ([`Solver::solve_from_rest`]): the cold
    /// solve the peer also makes.
    Rest(&'a Coefficients),
    /// A guess near the answer.
    Near(&'a Coefficients),
}

fn time_case(
    name: &'static str,
    finger: &Finger,
    load: &Load,
    start: Start<'_>,
    budget: Duration,
) -> anyhow::Result<Case> {
    let opts = tip_only();
    let mut solver = Solver::new(finger);
    let (median_us, runs, last) = median_us(budget, || {
        Ok(match start {
            Start::Scratch => solver.solve(load, None, &opts)?,
            Start::Rest(rest) => solver.solve_from_rest(load, rest, &opts)?,
            Start::Near(guess) => solver.solve(load, Some(guess), &opts)?,
        })
    })?;
    Ok(case(name, median_us, runs, &last))
}

fn case(name: &'static str, median_us: f64, runs: usize, s: &Solution) -> Case {
    Case {
        name,
        median_us,
        runs,
        iterations: s.report.iterations,
        residual: s.report.residual_norm,
        coupled: s.report.coupled,
        tip: s.tip,
    }
}

/// The four standard cases at N = 8.
fn standard_cases(budget: Duration) -> anyhow::Result<Vec<Case>> {
    let opts = tip_only();
    let f25 = Finger::paper(0.25, 8)?;
    let f40 = Finger::paper(0.4, 8)?;
    let unloaded = f25.solve(&Load::unloaded(), &opts)?;
    let near = f25.solve(
        &Load::unloaded().with_tip_force(0.95 * FX, 0.95 * FZ),
        &opts,
    )?;
    Ok(vec![
        time_case("unloaded", &f25, &Load::unloaded(), Start::Scratch, budget)?,
        time_case(
            "pressure",
            &f40,
            &Load::unloaded().with_pressure_kpa(386.0),
            Start::Scratch,
            budget,
        )?,
        time_case(
            "loaded_cold",
            &f25,
            &tip_load(),
            Start::Rest(&unloaded.coefficients),
            budget,
        )?,
        time_case(
            "loaded_warm",
            &f25,
            &tip_load(),
            Start::Near(&near.coefficients),
            budget,
        )?,
    ])
}

/// One row of the scaling table.
#[derive(Serialize)]
struct ScalingRow {
    elements: usize,
    loaded_cold_us: f64,
    iterations: usize,
    per_iteration_us: f64,
}

/// The per-iteration cost of the tip-loaded cold solve at N = 256 over
/// N = 32, the two timed alternately ([`paired_ratio`]).
#[derive(Serialize)]
struct ScalingRatio {
    from_elements: usize,
    to_elements: usize,
    per_iteration_ratio: f64,
}

fn scaling_ratio(budget: Duration, rows: &[ScalingRow]) -> anyhow::Result<ScalingRatio> {
    let opts = tip_only();
    let (from, to) = (SCALING_ELEMENTS[1], SCALING_ELEMENTS[3]);
    let iterations = |n: usize| {
        rows.iter()
            .find(|r| r.elements == n)
            .map_or(1, |r| r.iterations.max(1)) as f64
    };
    let (fa, fb) = (Finger::paper(0.25, from)?, Finger::paper(0.25, to)?);
    let (ua, ub) = (
        fa.solve(&Load::unloaded(), &opts)?,
        fb.solve(&Load::unloaded(), &opts)?,
    );
    let (mut sa, mut sb) = (Solver::new(&fa), Solver::new(&fb));
    let ratio = paired_ratio(
        budget,
        || Ok(sa.solve_from_rest(&tip_load(), &ua.coefficients, &opts)?),
        || Ok(sb.solve_from_rest(&tip_load(), &ub.coefficients, &opts)?),
    )?;
    Ok(ScalingRatio {
        from_elements: from,
        to_elements: to,
        per_iteration_ratio: ratio * iterations(from) / iterations(to),
    })
}

/// The tip-loaded cold solve (from the unloaded equilibrium) at each N.
fn scaling(budget: Duration) -> anyhow::Result<Vec<ScalingRow>> {
    let opts = tip_only();
    SCALING_ELEMENTS
        .iter()
        .map(|&n| {
            let f = Finger::paper(0.25, n)?;
            let unloaded = f.solve(&Load::unloaded(), &opts)?;
            let c = time_case(
                "scaling",
                &f,
                &tip_load(),
                Start::Rest(&unloaded.coefficients),
                budget,
            )?;
            Ok(ScalingRow {
                elements: n,
                loaded_cold_us: c.median_us,
                iterations: c.iterations,
                per_iteration_us: c.median_us / c.iterations.max(1) as f64,
            })
        })
        .collect()
}

/// The fastest configuration for a 0.01 mm tip, timed like `loaded_cold`
/// (fingers built, coarsest level started from its unloaded equilibrium),
/// with its distance from the N -> infinity reference.
#[derive(Serialize)]
struct ToTolerance {
    us: f64,
    /// Elements of the finest level.
    elements: usize,
    model: ModelId,
    tip_mm: [f64; 2],
    configuration: String,
    partition: PartitionKind,
    levels: Vec<usize>,
    extrapolated: bool,
    estimated_error_mm: Option<f64>,
    /// Distance from the reference tip (mm).
    error_mm: f64,
    reference_tip_mm: [f64; 2],
    reference_uncertainty_mm: Option<f64>,
    /// Its time over the N = 8 `loaded_cold` solve's, the two timed
    /// alternately ([`paired_ratio`]).
    ratio_to_n8_cold: f64,
    /// The coarsest level alone (its elements, from its rest state, to the
    /// relative residual an intermediate level is solved to) over the
    /// N = 8 `loaded_cold` solve, timed alternately: the floor of any
    /// configuration that estimates its error from this level and a finer
    /// one (docs/performance.md, "Where things stand").
    coarsest_level_ratio_to_n8_cold: f64,
}

/// The N -> infinity reference of the standard tip-loaded case: the
/// material partition at six levels (27 to 864 elements by default),
/// extrapolated, Newton to a relative residual of 1e-13.
fn reference(actuator: &Actuator) -> anyhow::Result<Solved> {
    let plan = Refinement {
        model: ModelId::default(),
        partition: PartitionKind::Material,
        start: 8,
        levels: 6,
        extrapolate: true,
    };
    let opts = SolveOptions {
        rtol: 1e-13,
        ..tip_only()
    };
    Ok(PlannedFinger::builder(actuator)
        .refinement(&plan)
        .build()?
        .solve(&tip_load(), &opts)?)
}

fn to_tolerance(budget: Duration) -> anyhow::Result<ToTolerance> {
    let act = Actuator::paper(0.25)?;
    let opts = tip_only();
    let model = ModelId::default();
    // the library's choice for the tolerance, with the levels it needed
    let chosen = PlannedFinger::builder(&act)
        .model(model)
        .plan(Plan::TipTolerance {
            tip_tol_mm: TIP_TOLERANCE_MM,
            start: None,
        })
        .build()?
        .solve(&tip_load(), &opts)?;
    let chosen = chosen
        .refinement
        .context("a tip tolerance records its refinement")?;
    let refiner = PlannedFinger::builder(&act)
        .refinement(&chosen.plan)
        .build()?;
    let unloaded = refiner.fingers()[0].solve(&Load::unloaded(), &opts)?;
    let (us, _, r) = median_us(budget, || {
        Ok(refiner.solve_from(&tip_load(), &unloaded.coefficients, &opts)?)
    })?;
    let n8 = Finger::paper(0.25, 8)?;
    let n8_unloaded = n8.solve(&Load::unloaded(), &opts)?;
    let mut n8_solver = Solver::new(&n8);
    let ratio_to_n8_cold = paired_ratio(
        budget,
        || Ok(n8_solver.solve_from_rest(&tip_load(), &n8_unloaded.coefficients, &opts)?),
        || Ok(refiner.solve_from(&tip_load(), &unloaded.coefficients, &opts)?),
    )?;
    // the floor: the first level alone, as the refinement solves it
    let coarsest = &refiner.fingers()[0];
    let coarse_opts = fpc::plan::intermediate_options(&opts, coarsest.len());
    let mut coarse_solver = Solver::new(coarsest);
    let coarsest_level_ratio_to_n8_cold = paired_ratio(
        budget,
        || Ok(n8_solver.solve_from_rest(&tip_load(), &n8_unloaded.coefficients, &opts)?),
        || Ok(coarse_solver.solve_from_rest(&tip_load(), &unloaded.coefficients, &coarse_opts)?),
    )?;
    let reference = reference(&act)?;
    let (tip, reference_tip) = (r.tip(), reference.tip());
    let error_mm = (tip[0] - reference_tip[0]).hypot(tip[1] - reference_tip[1]);
    let record = r
        .refinement
        .as_ref()
        .context("a refinement records its levels")?;
    Ok(ToTolerance {
        us,
        elements: r.elements(),
        model,
        tip_mm: tip,
        configuration: record.plan.label(),
        partition: record.plan.partition,
        levels: record.levels.iter().map(|l| l.elements).collect(),
        extrapolated: r.is_extrapolated(),
        estimated_error_mm: r.estimated_tip_error_mm(),
        error_mm,
        reference_tip_mm: reference_tip,
        reference_uncertainty_mm: reference.estimated_tip_error_mm(),
        ratio_to_n8_cold,
        coarsest_level_ratio_to_n8_cold,
    })
}

/// Our cold and warm cases against the peer's, run alternately.
#[derive(Serialize)]
struct PeerComparison {
    rounds: u32,
    peer_cold_us: f64,
    peer_warm_us: f64,
    fpc_cold_us: f64,
    fpc_warm_us: f64,
    /// Peer time over ours (above 1: we are faster), medians of the rounds.
    ratio_cold: f64,
    ratio_warm: f64,
    /// The same from each side's fastest round: both in the machine's fast
    /// phase (the estimator of `fpc-lab accuracy`; docs/performance.md).
    ratio_cold_fastest: f64,
    ratio_warm_fastest: f64,
    peer_cold_samples_us: Vec<f64>,
    peer_warm_samples_us: Vec<f64>,
    fpc_cold_samples_us: Vec<f64>,
    fpc_warm_samples_us: Vec<f64>,
}

fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    s.get(s.len() / 2).copied().unwrap_or(f64::NAN)
}

/// Runs the peer's driver once; its `cold_solve_us` and `warm_solve_us`.
fn run_peer(dir: &Path) -> anyhow::Result<(f64, f64)> {
    let driver = dir.join("driver");
    let out = std::process::Command::new(&driver)
        .arg("2000")
        .current_dir(dir)
        .output()
        .with_context(|| format!("cannot run the peer driver {}", driver.display()))?;
    anyhow::ensure!(
        out.status.success(),
        "the peer driver {} failed ({})",
        driver.display(),
        out.status
    );
    let text = String::from_utf8_lossy(&out.stdout);
    let value = |key: &str| -> anyhow::Result<f64> {
        text.lines()
            .find_map(|l| {
                let mut w = l.split_whitespace();
                (w.next() == Some(key)).then(|| w.next()?.parse::<f64>().ok())?
            })
            .filter(|v| v.is_finite() && *v > 0.0)
            .with_context(|| format!("the peer driver printed no `{key} <us>` line"))
    };
    Ok((value("cold_solve_us")?, value("warm_solve_us")?))
}

fn peer(dir: &Path, rounds: u32, budget: Duration) -> anyhow::Result<PeerComparison> {
    anyhow::ensure!(
        (1..=100).contains(&rounds),
        "--peer-rounds must lie in [1, 100], got {rounds}"
    );
    let mut s = PeerComparison {
        rounds,
        peer_cold_us: 0.0,
        peer_warm_us: 0.0,
        fpc_cold_us: 0.0,
        fpc_warm_us: 0.0,
        ratio_cold: 0.0,
        ratio_warm: 0.0,
        ratio_cold_fastest: 0.0,
        ratio_warm_fastest: 0.0,
        peer_cold_samples_us: Vec::new(),
        peer_warm_samples_us: Vec::new(),
        fpc_cold_samples_us: Vec::new(),
        fpc_warm_samples_us: Vec::new(),
    };
    for round in 0..rounds {
        crate::report::progress(&format!(
            "fpc-lab timing --peer: round {}/{rounds}",
            round + 1
        ));
        let (pc, pw) = run_peer(dir)?;
        s.peer_cold_samples_us.push(pc);
        s.peer_warm_samples_us.push(pw);
        let ours = standard_cases(budget)?;
        s.fpc_cold_samples_us.push(ours[2].median_us);
        s.fpc_warm_samples_us.push(ours[3].median_us);
    }
    crate::report::end_progress();
    s.peer_cold_us = median(&s.peer_cold_samples_us);
    s.peer_warm_us = median(&s.peer_warm_samples_us);
    s.fpc_cold_us = median(&s.fpc_cold_samples_us);
    s.fpc_warm_us = median(&s.fpc_warm_samples_us);
    s.ratio_cold = s.peer_cold_us / s.fpc_cold_us;
    s.ratio_warm = s.peer_warm_us / s.fpc_warm_us;
    let fastest = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
    s.ratio_cold_fastest = fastest(&s.peer_cold_samples_us) / fastest(&s.fpc_cold_samples_us);
    s.ratio_warm_fastest = fastest(&s.peer_warm_samples_us) / fastest(&s.fpc_warm_samples_us);
    Ok(s)
}

/// The JSON form.
#[derive(Serialize)]
struct Report<'a> {
    build: &'static str,
    cpu: Option<String>,
    unloaded: &'a Case,
    pressure: &'a Case,
    loaded_cold: &'a Case,
    loaded_warm: &'a Case,
    loaded_cold_tip_mm: [f64; 2],
    scaling: &'a [ScalingRow],
    scaling_ratio: &'a ScalingRatio,
    to_0p01mm: &'a ToTolerance,
    peer: Option<&'a PeerComparison>,
    provenance: crate::provenance::Provenance,
}

/// The CPU's model name, where the system says it (Linux).
fn cpu() -> Option<String> {
    let info = std::fs::read_to_string("/proc/cpuinfo").ok()?;
    info.lines()
        .find(|l| l.starts_with("model name"))
        .and_then(|l| l.split(':').nth(1))
        .map(|s| s.trim().to_string())
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let budget = Duration::from_millis(args.budget_ms.max(1));
    let cases = standard_cases(budget)?;
    let scaling = scaling(budget)?;
    let ratio = scaling_ratio(budget, &scaling)?;
    let to = to_tolerance(budget)?;
    let peer = match &args.peer {
        Some(dir) => Some(peer(dir, args.peer_rounds, budget)?),
        None => None,
    };
    let build = if cfg!(debug_assertions) {
        "debug"
    } else {
        "release"
    };
    let mut out = crate::output::stdout();
    if args.json {
        let r = Report {
            build,
            cpu: cpu(),
            unloaded: &cases[0],
            pressure: &cases[1],
            loaded_cold: &cases[2],
            loaded_warm: &cases[3],
            loaded_cold_tip_mm: cases[2].tip,
            scaling: &scaling,
            scaling_ratio: &ratio,
            to_0p01mm: &to,
            peer: peer.as_ref(),
            provenance: crate::provenance::Provenance::now(),
        };
        writeln!(out, "{}", serde_json::to_string(&r)?)?;
        return Ok(());
    }
    writeln!(
        out,
        "median time per solve ({build} build, N = 8, default actuator, tip-only output{})",
        cpu().map(|c| format!(", {c}")).unwrap_or_default()
    )?;
    writeln!(
        out,
        "{:<12} {:>12} {:>8} {:>11} {:>12}",
        "case", "median (us)", "runs", "iterations", "residual"
    )?;
    for c in &cases {
        writeln!(
            out,
            "{:<12} {:>12.2} {:>8} {:>11} {:>12.2e}",
            c.name, c.median_us, c.runs, c.iterations, c.residual
        )?;
    }
    writeln!(
        out,
        "loaded_cold tip: X = {:.6} mm, Z = {:.6} mm",
        cases[2].tip[0], cases[2].tip[1]
    )?;
    writeln!(
        out,
        "\nscaling: tip-loaded cold solve against N (equal elements)"
    )?;
    writeln!(
        out,
        "{:>9} {:>12} {:>11} {:>18}",
        "elements", "median (us)", "iterations", "per iteration (us)"
    )?;
    for r in &scaling {
        writeln!(
            out,
            "{:>9} {:>12.1} {:>11} {:>18.2}",
            r.elements, r.loaded_cold_us, r.iterations, r.per_iteration_us
        )?;
    }
    writeln!(
        out,
        "per-iteration cost ratio N = {} / N = {}: {:.2} (elements ratio {}; the two timed alternately)",
        ratio.to_elements,
        ratio.from_elements,
        ratio.per_iteration_ratio,
        ratio.to_elements / ratio.from_elements
    )?;
    writeln!(
        out,
        "\ntip within {TIP_TOLERANCE_MM} mm: {} ({} elements at the finest level, levels {:?}) in {:.1} us = {:.2} x the N = 8 cold solve (timed alternately with it)",
        to.configuration, to.elements, to.levels, to.us, to.ratio_to_n8_cold
    )?;
    writeln!(
        out,
        "  tip ({:.6}, {:.6}) mm, {:.2e} mm from the reference ({:.6}, {:.6}) mm (uncertainty {:.1e} mm); estimated {:.2e} mm",
        to.tip_mm[0],
        to.tip_mm[1],
        to.error_mm,
        to.reference_tip_mm[0],
        to.reference_tip_mm[1],
        to.reference_uncertainty_mm.unwrap_or(f64::NAN),
        to.estimated_error_mm.unwrap_or(f64::NAN)
    )?;
    writeln!(
        out,
        "  its first level alone ({} elements): {:.2} x the N = 8 cold solve (timed alternately with it)",
        to.levels.first().copied().unwrap_or(0),
        to.coarsest_level_ratio_to_n8_cold
    )?;
    if let Some(p) = &peer {
        writeln!(
            out,
            "\npeer ({} alternating rounds, medians): cold {:.1} us vs ours {:.1} us = {:.2}x; warm {:.1} us vs ours {:.1} us = {:.2}x",
            p.rounds, p.peer_cold_us, p.fpc_cold_us, p.ratio_cold, p.peer_warm_us, p.fpc_warm_us, p.ratio_warm
        )?;
        writeln!(
            out,
            "peer, fastest rounds: cold {:.2}x, warm {:.2}x",
            p.ratio_cold_fastest, p.ratio_warm_fastest
        )?;
    }
    Ok(())
}
