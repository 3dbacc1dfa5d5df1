//! Time schemes. A [`Scheme`] holds the parameters; [`Scheme::prepare`] assembles and factors the
//! constant step matrix once and returns an [`Integrator`] whose [`Integrator::step`] advances one
//! time step with the contact law enforced at the new time level.
//!
//! | name | file | order (smooth) | contact law |
//! |---|---|---|---|
//! | `newmark` | [`newmark`] | 2 (γ = ½) | position, t_{n+1} |
//! | `hht` | [`hht`] | 2 | position, t_{n+1} |
//! | `backward_euler` | [`backward_euler`] | 1 | position, t_{n+1} |
//! | `paoli_schatzman` | [`paoli_schatzman`] | 2 | position, `(U_{n+1} + e U_{n−1})/(1+e)` |
//! | `moreau_jean` | [`moreau_jean`] | 1 (2 for θ = ½ without impacts) | velocity + restitution e |
//! | `central_difference` | [`central_difference`] | 2, CFL-limited | position, t_{n+1} |

pub mod backward_euler;
pub mod carpenter;
pub mod central_difference;
pub mod contact_stabilised_newmark;
pub mod explicit_penalty;
pub mod hauret_le_tallec;
pub mod hht;
pub mod kane;
pub mod laursen_chawla;
pub mod moreau_jean;
pub mod newmark;
pub mod paoli_schatzman;
pub mod scheme;
pub mod step;
pub mod taylor_flanagan;

use crate::error::Result;
use crate::param::{Entry, Params};
pub use scheme::{check_friction, Integrator, Scheme, Solvers, State, StepInfo};
pub use step::{LinearSolver, DEFAULT_LINEAR_SOLVER, LINEAR_SOLVERS};

/// The schemes, one registry line each (their parameters are declared in their files).
pub const SCHEMES: &[Entry<dyn Scheme>] = &[
    newmark::ENTRY,
    hht::ENTRY,
    backward_euler::ENTRY,
    paoli_schatzman::ENTRY,
    moreau_jean::ENTRY,
    central_difference::ENTRY,
    laursen_chawla::ENTRY,
    carpenter::ENTRY,
    taylor_flanagan::ENTRY,
    explicit_penalty::ENTRY,
    kane::ENTRY,
    contact_stabilised_newmark::ENTRY,
    hauret_le_tallec::ENTRY,
];

/// The registry entry of the scheme called `name`.
pub fn entry(name: &str) -> Result<&'static Entry<dyn Scheme>> {
    crate::param::find(SCHEMES, "scheme", name)
}

/// The scheme called `name` with its parameters read from `p` and validated.
pub fn by_name(name: &str, p: &Params) -> Result<Box<dyn Scheme>> {
    (entry(name)?.build)(p)
}
