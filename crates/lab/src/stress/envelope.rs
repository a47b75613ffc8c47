//! The validity envelope's bounds ([`inside_envelope`](super::inside_envelope);
//! docs/stress.md says how they were found and checks them on other seeds).

/// Largest prestrain: above it the mid-plane strain of the unloaded
/// finger nears its 0.20 limit, and the prestressed layer's strain its
/// 0.6 limit once pressure stretches it.
pub const MAX_EPS0: f64 = 0.5;
/// Largest pressure (kPa): above it the fluidic layer's stretch takes
/// the strains past their limits and, on thin stacks, the reversed
/// curl closes on itself.
pub const MAX_PRESSURE_KPA: f64 = 400.0;
/// The pressure (kPa) whose uncurling offsets a prestrain of 1 in the
/// curl estimate ([`StressInputs::curl`](super::StressInputs::curl)).
pub const PRESSURE_PER_PRESTRAIN_KPA: f64 = 1000.0;
/// Largest curl estimate `|eps0 - P / 1000 kPa| lx / H`: the paper's
/// finger at eps0 = 0.25 has 3.4; from about 6.7 on, the unloaded (or
/// the reversed) finger turns through a full circle into self contact
/// (the self-contact search with its clearance proof finds it there; the
/// sampled one of the first envelope search found it from about 7.5, and
/// the bound was 7).
pub const MAX_CURL: f64 = 6.5;
/// Largest load strain `|F| lx H / D` over eps0: a tip load whose
/// bending strain `M z / D` (at `M = |F| lx`, `z = H`) reaches a
/// fraction of the prestrain compresses the prestressed layer below
/// zero strain (folding) or stretches the laminate past the strain
/// limits (unfolding).
pub const MAX_LOAD_STRAIN_OVER_EPS0: f64 = 0.15;
/// Longest element of a drawn partition over `lx`: elements of at most
/// `lx / 12` stay within the slope limit wherever the curl estimate
/// does (the automatic partition needs no bound: it splits).
pub const MAX_ELEMENT_FRACTION: f64 = 1.0 / 12.0;
