//! The toolkit a scheme's file is written with: the state and bookkeeping of a step
//! ([`stepper`]), the constant step operator with its contact coupling ([`contact_step`]),
//! solved directly ([`direct`]) or by CG ([`iterative`]), the stability limit of the explicit
//! schemes ([`cfl`]), the explicit step with a lumped mass and a contact force at t_n
//! ([`explicit`]), and the trapezoidal step with a predictor that the midpoint-type schemes
//! share ([`trapezoidal`]).
//!
//! Each step of an implicit scheme solves `A X = r − c B_Nᵀ λ` (`A = m M + k K` constant) with
//! λ from a complementarity law on `o − B_N X` ([`ContactStep::solve`]); the offsets `o` carry
//! the law's level:
//! - position (Signorini at the new level: Newmark, HHT, backward Euler): `o = g₀`;
//! - on a combination of levels (Paoli–Schatzman): `o = g₀`, X the combination;
//! - velocity with an index set (Moreau–Jean): `o_i = −e (B_N V_n)_i` on the set, `+∞` off it
//!   (excluded: λ_i = 0); a persistency law on gap increments takes `o = g₀ − g_n` on its set;
//! - an explicit multiplier (central difference): `A` holds only the massless block of K;
//! - an explicit force at t_n with a lumped mass and a law of the scheme's own (forward-increment
//!   multiplier, velocity correction, penalty): no step operator, [`explicit`];
//! - a projection in a norm (a predictor `argmin ‖w − x‖_M` over the admissible set): a second
//!   [`ContactStep`] with `A = M`.
//!
//! The law itself is the formulation's ([`crate::contact::Solver`]), or one the scheme passes
//! ([`ContactStep::solve_with`]).

pub mod cfl;
pub mod compliant;
pub mod contact_step;
pub mod direct;
pub mod explicit;
pub mod friction;
pub mod iterative;
pub mod stepper;
pub mod trapezoidal;

pub use contact_step::{
    cg_pays, stiffness_weight, ContactStep, LinearSolver, AUTO_CG_DOFS, AUTO_DIRECT_WEIGHT_2D,
    DEFAULT_LINEAR_SOLVER, LINEAR_SOLVERS,
};
pub use friction::FrictionStep;
pub use stepper::{initial_acceleration, time_step, Stepper, ThreeLevel};
pub use trapezoidal::Trapezoidal;
