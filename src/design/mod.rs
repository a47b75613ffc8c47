//! Inverse design: from the objects a gripper must hold to the design to
//! build (`fpc design`).
//!
//! A design is a point `x = (eps0, mounting angle in degrees, overlap in
//! mm)`; the requirements ([`Requirements`]) say which of them vary and
//! within which bounds. Each requirement becomes normalised margins, 0 at
//! the limit and positive when met ([`evaluate`]):
//!
//! - a cuboid of widths `[d0, d1]` with lift `L` per finger: at `CUBOID_SAMPLES`
//!   widths across the range, the width must fit (`d <= d_max`, margin
//!   `(d_max - d) / d`), the grasp at full friction (`f = mu F`, angle 0)
//!   must be valid, and `(mu F - L) / L >= 0`; with `max_normal_n` also
//!   `(F_max - F) / F_max >= 0`;
//! - a sphere of radii `[r0, r1]` with lift `L`: at `SPHERE_SAMPLES` radii,
//!   the best valid grasping angle's lift ([`Gripper::max_sphere_lift`](crate::Gripper::max_sphere_lift))
//!   gives `(f_v - L) / L`;
//! - opening: the unloaded finger at `pressure_kpa` gives a grasp size of
//!   at least `size_mm`: `(d(P) - size) / size`.
//!
//! A grasp that cannot be solved or holds nothing scores -1, a gripper
//! that cannot be built [`UNBUILDABLE_MARGIN`], -2. A margin above that
//! is as written down to -1; below -1 (a requirement missed by more than
//! itself: a normal force three times its limit, a lift against the
//! weight) it is compressed into (-2, -1) as `-2 + 1 / (-m)`, monotone
//! and with its slope continuous at -1, so that a gripper that can be
//! built always ranks above one that cannot however small the limit a
//! margin is normalised by; the margin's `detail` and `value` keep the
//! quantity itself.
//!
//! Every size, force and opening a margin is normalised by is bounded
//! below and above when the requirements are read
//! ([`LENGTH_RANGE_MM`], [`FORCE_RANGE_N`], [`MU_RANGE`], and at most
//! [`MAX_OBJECTS`] objects; the requirements module docs list every
//! bound), so every margin and every sensitivity is finite; [`optimize`]
//! and [`grid_search`] check the requirements again before any work, for
//! a caller that built them without [`Requirements::parse`].
//!
//! The design with the largest worst-case margin is found by a multistart
//! trust-region ascent of the worst margin ([`optimize`]; with
//! [`optimize_with_progress`], the caller sees how far it has got:
//! [`DesignProgress`]); [`grid_search`] is the brute-force check. Every grasp a
//! design claims is a forward solve through the ordinary gripper path, and
//! [`Designed::scenes`] writes one scene file per object that `fpc solve`
//! runs to reproduce it.

mod best_grasp;
mod evaluate;
mod limits;
mod minimax;
mod optimize;
mod progress;
mod reproduce;
mod requirements;
mod variables;

pub use evaluate::{
    evaluate, Evaluation, Margin, CUBOID_SAMPLES, SPHERE_SAMPLES, UNBUILDABLE_MARGIN,
};
pub use variables::gripper;

pub use limits::{FORCE_RANGE_N, LENGTH_RANGE_MM, MAX_OBJECTS, MU_RANGE};
pub use optimize::{
    grid_search, optimize, optimize_with_progress, DesignOptions, Designed, GridResult,
    MarginSensitivity, MAX_ASCENTS, MAX_ASCENT_ITERATIONS, MAX_GRID_POINTS, MAX_RANDOM_STARTS,
};
pub use progress::{DesignProgress, DesignStage};
pub use reproduce::{reproduce, Reproduction, REPRODUCE_RTOL};
pub use requirements::{
    DesignBase, ObjectRequirement, OpenRequirement, Requirements, RequirementsError, Vary,
    DEFAULT_DESIGN, VARIABLES,
};
