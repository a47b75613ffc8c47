//! Solving a finger: decoupled element solves without a tip load, the
//! coupled system with one, continuation where Newton alone fails, and the
//! finishing of a [`Solution`] (tip, energy, stability, shape, validity).

use fpc_newton::{BorderedNewton, Hessian, Newton, NewtonOptions, Report, Termination};

use crate::error::Warning;

use crate::circle_fit::fit_circle;
use crate::model::{ElementModel, Vector};
use crate::solve_error::SolveError;

use super::chain::Chain;
use super::element_solve::{local_workspace, solve_element, Local, Single};
use super::load::Load;
use super::newton_policy::{
    chain_straight, fixed_cap, minimize_straight, newton_flags, newton_options, shifted_instead,
};
use super::options::{check_guess, Solution, SolveOptions, SolveReport, StepCounts, Strategy};
use super::pool::{Pooled, Spare, UnloadedStart, WorkspacePool};
use super::problem::FingerCore;
use crate::coefficients::Coefficients;

/// Validity checks per element of every solution (the ends of 4 equal
/// sub-intervals; the paper's element is monotone in x, so its extremes
/// are at the ends): [`Finger::validity`](super::Finger::validity) at this
/// count gives a solution's findings.
pub const VALIDITY_SAMPLES: usize = 4;

/// Hands the buffers to the next solver of the finger.
impl<M: ElementModel> Drop for SolverCore<'_, M> {
    fn drop(&mut self) {
        let spare = Spare {
            chain: self.chain.take_parts(),
            newton: std::mem::replace(&mut self.newton, Newton::new(0, NewtonOptions::default())),
            y: std::mem::take(&mut self.y),
            start: std::mem::take(&mut self.start),
            unloaded: self.unloaded.take(),
        };
        self.pool.put(spare);
    }
}

/// The state of a tip-only solve ([`SolverCore::solve_tip`]).
#[derive(Debug, Clone)]
pub(crate) struct TipSolve {
    /// Raw coefficients.
    pub coefficients: Coefficients,
    /// Tip (mm, finger frame).
    pub tip: [f64; 2],
    /// End tangent angle (rad).
    pub end_angle: f64,
    /// Newton iterations.
    pub iterations: usize,
    /// Where they went.
    pub steps: StepCounts,
}

/// A reusable solver workspace for model `M`.
pub(crate) struct SolverCore<'a, M: ElementModel> {
    pub finger: &'a FingerCore<M>,
    /// Where the buffers go when the solver is dropped.
    pool: &'a WorkspacePool<M>,
    /// The finger's warnings (actuator, law), copied into every solution.
    pub warnings: &'a [Warning],
    pub chain: Chain<'a, M>,
    pub newton: Newton,
    /// The bordered solver's workspace, made by the first target solve.
    pub bordered: Option<BorderedNewton>,
    /// One element's Newton and Hessian (decoupled solves), made when first
    /// needed: a solver that only runs coupled solves (a refinement level)
    /// allocates neither.
    local: Option<Local>,
    /// Scaled unknowns.
    pub y: Vec<f64>,
    /// The start of a coupled solve, kept for a continuation restart.
    start: Vec<f64>,
    /// The unloaded start of the last cold coupled solve.
    unloaded: Option<UnloadedStart>,
    /// Pi at the end of the last coupled Newton solve (taken by `finish`).
    final_energy: Option<f64>,
    /// What the callers' guesses are.
    pub guess: Guess,
    /// Whether a chain doubles its shifted steps ([`newton_flags`]); off
    /// only to take a failed refinement again as before (`plan::Auto`).
    pub double_shifted: bool,
}

/// What a caller's guess is, which decides how Newton takes it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) enum Guess {
    /// Near the answer (a nearby load's equilibrium): Newton in the scaled
    /// unknowns.
    #[default]
    Near,
    /// Close to the answer (a nested refinement level's prolongated
    /// state): as `Near`, with Newton's `trusted_start`.
    Trusted,
    /// The scene's rest state, its equilibrium without the tip force
    /// ([`super::Solver::solve_from_rest`]): far from a tip-loaded answer,
    /// so taken as a cold solve takes its own start (the straightened
    /// unknowns), but without the batch's kept first Hessian.
    Rest,
}

impl<'a, M: ElementModel> SolverCore<'a, M> {
    pub fn new(pooled: &'a Pooled<M>, warnings: &'a [Warning]) -> SolverCore<'a, M> {
        let Pooled { core: finger, pool } = pooled;
        let dim = M::Coeffs::LEN * finger.len();
        let spare = pool.take().filter(|s| s.y.len() == dim);
        let (chain, newton, y, start, unloaded) = match spare {
            Some(s) => (Some(s.chain), s.newton, s.y, s.start, s.unloaded),
            None => (
                None,
                Newton::new(dim, NewtonOptions::default()),
                vec![0.0; dim],
                vec![0.0; dim],
                None,
            ),
        };
        SolverCore {
            finger,
            pool,
            warnings,
            chain: Chain::with_parts(finger, chain),
            newton,
            bordered: None,
            local: None,
            y,
            start,
            unloaded,
            final_energy: None,
            guess: Guess::Near,
            double_shifted: true,
        }
    }

    /// Solves a scene; `guess` are raw coefficients.
    pub fn solve(
        &mut self,
        load: &Load,
        guess: Option<&Coefficients>,
        opts: &SolveOptions,
    ) -> Result<Solution, SolveError> {
        let (report, decoupled) = self.equilibrium(load, guess, opts)?;
        self.finish(load, opts, report, decoupled)
    }

    /// Solves a scene for the tip alone: the state, its tip and end angle,
    /// without the energy, stability, shape or validity findings of a
    /// [`Solution`] (a refinement's intermediate level, whose state only
    /// starts the next one).
    pub fn solve_tip(
        &mut self,
        load: &Load,
        guess: Option<&Coefficients>,
        opts: &SolveOptions,
    ) -> Result<TipSolve, SolveError> {
        let (report, _) = self.equilibrium(load, guess, opts)?;
        self.final_energy = None;
        let f = self.finger;
        let coefficients = self.coefficients();
        let k = coefficients.as_slice();
        let (tip, end_angle) = crate::element::walk::tip_and_end_angle(&f.elements, k);
        if !(tip.iter().all(|v| v.is_finite()) && end_angle.is_finite()) {
            return Err(SolveError::NotConverged {
                reason: Termination::NonFinite,
                iterations: report.iterations,
                relative_residual: f64::INFINITY,
                element: None,
                last: coefficients,
            });
        }
        Ok(TipSolve {
            coefficients,
            tip,
            end_angle,
            iterations: report.iterations,
            steps: report.steps,
        })
    }

    /// The equilibrium of a scene in `self.y`, with its report and whether
    /// it was solved element by element.
    fn equilibrium(
        &mut self,
        load: &Load,
        guess: Option<&Coefficients>,
        opts: &SolveOptions,
    ) -> Result<(SolveReport, bool), SolveError> {
        crate::cancel::check()?;
        load.validate()?;
        let f = self.finger;
        opts.validate_on(f.len())?;
        if let Some(g) = guess {
            check_guess(g, f.len(), M::Coeffs::LEN)?;
        }
        let nopts = NewtonOptions {
            trusted_start: self.guess == Guess::Trusted && guess.is_some(),
            ..newton_flags(
                newton_options(opts.rtol * f.stiffness, opts)?,
                f.len() == 1,
                self.double_shifted,
            )
        };
        // validated above: setting cannot fail
        let _ = self.newton.set_options(nopts);
        let decoupled = !load.has_tip_load() && opts.strategy == Strategy::Auto;
        let mut report = if decoupled {
            self.solve_decoupled(load, guess, opts.continuation)?
        } else {
            self.solve_coupled(load, guess, opts)?
        };
        report.residual_norm /= f.stiffness;
        Ok((report, decoupled))
    }

    pub fn load_guess(&mut self, guess: Option<&Coefficients>) {
        match guess {
            Some(g) => self.finger.scale_into(g.as_slice(), &mut self.y),
            None => self.y.fill(0.0),
        }
    }

    fn solve_decoupled(
        &mut self,
        load: &Load,
        guess: Option<&Coefficients>,
        continuation: bool,
    ) -> Result<SolveReport, SolveError> {
        self.load_guess(guess);
        let f = self.finger;
        let n = M::Coeffs::LEN;
        let mut rep = SolveReport {
            reason: Termination::Converged,
            iterations: 0,
            residual_norm: 0.0,
            evaluations: 0,
            coupled: false,
            continuation_steps: 0,
            steps: StepCounts::default(),
        };
        for i in 0..f.len() {
            let d = f.distinct[i];
            if d != i {
                let (a, b) = self.y.split_at_mut(n * i);
                b[..n].copy_from_slice(&a[n * d..n * d + n]);
                continue;
            }
            let local = local_workspace::<M>(&mut self.local, &self.newton);
            let mut p = Single::<M>::new(f, i, load.scalars(), &mut local.matrix);
            let warm = guess.is_none() && i > 0;
            if warm {
                // neighbouring elements strain and curve alike: start from
                // the last solved one's raw coefficients (raw unknowns do
                // not depend on the length; the scaled ones do)
                let (sp, si) = (f.unscale[i - 1], f.unscale[i]);
                let (a, b) = self.y.split_at_mut(n * i);
                for j in 0..n {
                    b[j] = a[n * (i - 1) + j] * sp[j] / si[j];
                }
            }
            let y = &mut self.y[n * i..n * i + n];
            let start = M::Coeffs::from_fn(|j| y[j]);
            let mut r = solve_element(&mut local.newton, &mut p, y, warm, continuation, &mut rep);
            if !r.reason.is_converged() {
                // (the report counts both attempts; a failure names the
                // shifted one's iterations, as the coupled path does)
                if let Some(current) = shifted_instead(&mut local.newton) {
                    y.copy_from_slice(start.as_ref());
                    r = solve_element(&mut local.newton, &mut p, y, warm, continuation, &mut rep);
                    let _ = local.newton.set_options(current);
                }
            }
            rep.residual_norm = rep.residual_norm.max(r.residual_norm);
            if !r.reason.is_converged() {
                return Err(self.not_converged(&r, Some(i)));
            }
        }
        Ok(rep)
    }

    fn solve_coupled(
        &mut self,
        load: &Load,
        guess: Option<&Coefficients>,
        opts: &SolveOptions,
    ) -> Result<SolveReport, SolveError> {
        let mut base = SolveReport {
            reason: Termination::Converged,
            iterations: 0,
            residual_norm: 0.0,
            evaluations: 0,
            coupled: true,
            continuation_steps: 0,
            steps: StepCounts::default(),
        };
        let start_load = Load {
            fx: 0.0,
            fz: 0.0,
            ..*load
        };
        let mut start_failed = false;
        match guess {
            Some(g) => self.load_guess(Some(g)),
            None => {
                // the unloaded equilibrium at the same pressure (the last
                // cold solve's, when it started from the same)
                match self.unloaded_start(&start_load, opts) {
                    Ok(r) => {
                        base.iterations += r.iterations;
                        base.evaluations += r.evaluations;
                        base.continuation_steps += r.continuation_steps;
                        base.steps = r.steps;
                    }
                    Err(SolveError::NotConverged { iterations, .. }) if opts.continuation => {
                        // no unloaded equilibrium to start from (a curl the
                        // elements cannot follow, which the load may undo):
                        // Newton from the straight finger, and no load
                        // continuation (it needs an equilibrium to start)
                        base.iterations += iterations;
                        base.steps.element += iterations;
                        self.load_guess(None);
                        start_failed = true;
                    }
                    Err(e) => return Err(e),
                }
            }
        }
        self.start.copy_from_slice(&self.y);
        // the kind of the caller's guess, or None for the solve's own start
        let start = guess.map(|_| self.guess);
        let mut r = self.load_from_start(load, start, opts, start_failed, &mut base);
        if r.is_err() {
            if let Some(current) = shifted_instead(&mut self.newton) {
                self.y.copy_from_slice(&self.start);
                r = self.load_from_start(load, start, opts, start_failed, &mut base);
                let _ = self.newton.set_options(current);
            }
        }
        r.map(|()| base)
    }

    /// The decoupled equilibrium of `load` in `self.y`: the one kept from
    /// the last cold solve when it is of the same load and options
    /// ([`UnloadedStart`]), else solved (and kept).
    fn unloaded_start(
        &mut self,
        load: &Load,
        opts: &SolveOptions,
    ) -> Result<SolveReport, SolveError> {
        if let Some(kept) = &self.unloaded {
            if kept.load == *load && kept.opts == *opts {
                self.y.copy_from_slice(&kept.y);
                return Ok(kept.report.clone());
            }
        }
        let report = self.solve_decoupled(load, None, opts.continuation)?;
        // the kept buffer reused: a run of cold solves at changing
        // pressures allocates nothing here
        let mut y = self.unloaded.take().map(|k| k.y).unwrap_or_default();
        y.clone_from(&self.y);
        self.unloaded = Some(UnloadedStart {
            load: *load,
            opts: *opts,
            y,
            report: report.clone(),
        });
        Ok(report)
    }

    /// Newton on the loaded chain from `self.y` (the start), and load
    /// continuation from the start where that fails; counts go to `base`.
    ///
    /// A chain of several elements grows its step cap and doubles its
    /// shifted steps ([`newton_flags`]); where that attempt fails,
    /// everything after it (Newton again from the start if the cap grew or
    /// a step was doubled, then the continuation) keeps the fixed cap and
    /// the shifted steps as the shift gives them, so a solve that converged
    /// that way still does.
    fn load_from_start(
        &mut self,
        load: &Load,
        start: Option<Guess>,
        opts: &SolveOptions,
        start_failed: bool,
        base: &mut SolveReport,
    ) -> Result<(), SolveError> {
        let mut r = self.direct(load, start, start_failed, base);
        if r.reason.is_converged() {
            return Ok(());
        }
        let current = *self.newton.options();
        let grown_chain = current.step_growth && !current.modified_pivots;
        if grown_chain {
            // the same validated options with flags off: cannot fail
            let _ = self.newton.set_options(fixed_cap(current));
            if r.grown_steps > 0 || r.extended_steps > 0 {
                self.y.copy_from_slice(&self.start);
                r = self.direct(load, start, start_failed, base);
            }
        }
        let out = if r.reason.is_converged() {
            Ok(())
        } else {
            self.continue_load(load, opts, start_failed, &r, base)
        };
        if grown_chain {
            let _ = self.newton.set_options(current);
        }
        out
    }

    /// Newton on the loaded chain from `self.y`; counts go to `base`, and
    /// a converged solve's energy to `final_energy`.
    fn direct(
        &mut self,
        load: &Load,
        start: Option<Guess>,
        start_failed: bool,
        base: &mut SolveReport,
    ) -> Report {
        self.chain.set_load(load);
        // a cold solve's first Hessian is at its unloaded start, which the
        // cold solves of a batch share (`Chain::from_start`)
        self.chain.from_start = start.is_none() && !start_failed;
        let near = matches!(start, Some(Guess::Near | Guess::Trusted));
        let r = minimize_straight::<M, _>(
            &mut self.newton,
            &mut self.chain,
            chain_straight,
            &mut self.y,
            near,
        );
        base.iterations += r.iterations;
        base.steps.coupled += r.iterations;
        base.steps.globalisation(&r);
        base.evaluations += r.energy_evals + r.gradient_evals + r.hessian_evals;
        base.residual_norm = r.residual_norm;
        if r.reason.is_converged() {
            self.final_energy = Some(r.energy);
        }
        r
    }

    /// Load continuation from the start, `F(t) = t F`, after the direct
    /// solve `r` failed (where the options allow it).
    fn continue_load(
        &mut self,
        load: &Load,
        opts: &SolveOptions,
        start_failed: bool,
        r: &Report,
        base: &mut SolveReport,
    ) -> Result<(), SolveError> {
        if !opts.continuation || !load.has_tip_load() || start_failed {
            return Err(self.not_converged(r, None));
        }
        // load continuation from the start point: F(t) = t F
        self.y.copy_from_slice(&self.start);
        let chain = &mut self.chain;
        let newton = &mut self.newton;
        let copts = fpc_newton::ContinuationOptions::default();
        let steps = &mut base.steps;
        let cr = fpc_newton::continuation(0.0, 1.0, &mut self.y, &copts, |t, y| {
            chain.set_load(&Load {
                fx: t * load.fx,
                fz: t * load.fz,
                ..*load
            });
            let r = minimize_straight::<M, _>(newton, chain, chain_straight, y, false);
            steps.continuation += r.iterations;
            steps.globalisation(&r);
            r
        });
        base.iterations += cr.newton_iterations;
        base.continuation_steps += cr.steps;
        base.residual_norm = cr.last.residual_norm;
        if cr.complete && cr.last.reason.is_converged() {
            self.chain.set_load(load);
            self.final_energy = Some(cr.last.energy);
            Ok(())
        } else {
            Err(self.not_converged(&cr.last, None))
        }
    }

    pub fn coefficients(&self) -> Coefficients {
        self.finger.raw(&self.y)
    }

    pub fn not_converged(&self, r: &Report, element: Option<usize>) -> SolveError {
        SolveError::NotConverged {
            reason: r.reason,
            iterations: r.iterations,
            relative_residual: r.residual_norm / self.finger.stiffness,
            element,
            last: self.coefficients(),
        }
    }

    /// The Hessian's negative eigenvalues at the current state (`None`
    /// when it cannot be factorised: singular).
    fn negative_eigenvalues(&mut self, load: &Load, decoupled: bool) -> Option<usize> {
        let f = self.finger;
        let n = M::Coeffs::LEN;
        if decoupled {
            let mut negative = 0;
            let mut g = vec![0.0; n];
            let local = local_workspace::<M>(&mut self.local, &self.newton);
            for i in 0..f.len() {
                let mut p = Single::<M>::new(f, i, load.scalars(), &mut local.matrix);
                p.hessian(&self.y[n * i..n * i + n], &mut g);
                // equal elements have equal Hessians
                let count = f.distinct.iter().filter(|&&d| d == f.distinct[i]).count();
                if f.distinct[i] == i {
                    negative += count * p.matrix.inertia(0.0).ok()?.negative;
                }
            }
            Some(negative)
        } else {
            let mut g = vec![0.0; self.y.len()];
            self.chain.set_load(load);
            self.chain.hessian(&self.y, &mut g);
            self.chain.inertia().map(|i| i.negative)
        }
    }

    pub fn finish(
        &mut self,
        load: &Load,
        opts: &SolveOptions,
        report: SolveReport,
        decoupled: bool,
    ) -> Result<Solution, SolveError> {
        let f = self.finger;
        let k = self.coefficients();
        let (found, tip, end_angle) =
            crate::validity::check(&f.elements, &f.laminate(), k.as_slice(), VALIDITY_SAMPLES);
        // a coupled Newton solve already knows Pi at its final point
        let energy = self
            .final_energy
            .take()
            .unwrap_or_else(|| f.energy_raw(load, k.as_slice()));
        let negative_eigenvalues = if opts.stability {
            self.negative_eigenvalues(load, decoupled)
        } else {
            None
        };
        let (points, radius) = if opts.shape {
            let pts = f.shape_raw(k.as_slice(), opts.samples_per_element);
            let r = fit_circle(&pts).map(|c| c.radius);
            (pts, r)
        } else {
            (Vec::new(), None)
        };
        let values_finite =
            tip.iter().all(|v| v.is_finite()) && energy.is_finite() && end_angle.is_finite();
        if !values_finite {
            return Err(SolveError::NotConverged {
                reason: Termination::NonFinite,
                iterations: report.iterations,
                relative_residual: f64::INFINITY,
                element: None,
                last: k,
            });
        }
        let mut warnings = self.warnings.to_vec();
        warnings.extend(found);
        Ok(Solution {
            coefficients: k,
            tip,
            end_angle,
            energy,
            negative_eigenvalues,
            stable: negative_eigenvalues.map(|k| k == 0),
            points,
            radius,
            element_lengths: f.lengths.clone(),
            warnings,
            report,
        })
    }
}
