//! The buffers a finger's solvers hand on: a dropped solver leaves its
//! chain, Newton workspace, unknowns and the last cold solve's unloaded
//! start in the finger's pool, and the next solver takes them instead of
//! allocating its own.

use std::sync::Mutex;

use fpc_newton::Newton;

use crate::model::ElementModel;

use super::chain::ChainParts;
use super::load::Load;
use super::options::{SolveOptions, SolveReport};
use super::problem::FingerCore;

/// The buffers of a dropped solver, which the next solver of the same
/// finger takes instead of allocating its own ([`WorkspacePool`]).
pub(crate) struct Spare<M: ElementModel> {
    pub chain: ChainParts<M>,
    pub newton: Newton,
    pub y: Vec<f64>,
    pub start: Vec<f64>,
    pub unloaded: Option<UnloadedStart>,
}

/// The start of a cold coupled solve: the decoupled equilibrium of `load`
/// (a scene without its tip load) under `opts`, in scaled unknowns, and its
/// report. The next cold solve from the same start takes it instead of
/// solving the elements again: the element solves are deterministic (from
/// the straight finger, each element from the last), so it is bit for bit
/// what they would give, report included.
#[derive(Debug, Clone)]
pub(crate) struct UnloadedStart {
    pub load: Load,
    pub opts: SolveOptions,
    pub y: Vec<f64>,
    pub report: SolveReport,
}

/// One spare solver workspace per finger: `Finger::solve` builds a solver
/// per call, and a refinement one per level, and each would otherwise
/// allocate some twenty buffers. Solvers of the same finger on other
/// threads at the same time allocate their own.
pub(crate) struct WorkspacePool<M: ElementModel>(Mutex<Option<Spare<M>>>);

impl<M: ElementModel> WorkspacePool<M> {
    pub fn take(&self) -> Option<Spare<M>> {
        self.0.try_lock().ok().and_then(|mut s| s.take())
    }

    pub fn put(&self, spare: Spare<M>) {
        if let Ok(mut s) = self.0.try_lock() {
            *s = Some(spare);
        }
    }
}

impl<M: ElementModel> Default for WorkspacePool<M> {
    fn default() -> Self {
        WorkspacePool(Mutex::new(None))
    }
}

/// A copy of a finger starts without a spare workspace.
impl<M: ElementModel> Clone for WorkspacePool<M> {
    fn clone(&self) -> Self {
        WorkspacePool::default()
    }
}

/// A finger's elements with the spare workspace of its solvers.
#[derive(Debug, Clone)]
pub(crate) struct Pooled<M: ElementModel> {
    pub core: FingerCore<M>,
    pub pool: WorkspacePool<M>,
}

impl<M: ElementModel> Pooled<M> {
    pub fn new(core: FingerCore<M>) -> Pooled<M> {
        Pooled {
            core,
            pool: WorkspacePool::default(),
        }
    }
}

impl<M: ElementModel> std::ops::Deref for Pooled<M> {
    type Target = FingerCore<M>;

    fn deref(&self) -> &FingerCore<M> {
        &self.core
    }
}

impl<M: ElementModel> std::fmt::Debug for WorkspacePool<M> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("WorkspacePool")
    }
}
