//! The 0D discretisation: a point mass m on a spring of stiffness k above the rigid plane, one
//! node and one dof, its height u (`shared/reference/spring_mass.md`):
//! `m ü + k u = f − B_Nᵀ λ` with `B_N = −1` (the outward normal points down) and `g = u`.
//! Its [`MassModel`] is one "element" of one node carrying m, whose dof is the contact dof.

use crate::error::Result;
use crate::fem::mass_model::{ElementMass, MassModel};
use crate::linalg::TripletBuilder;
use crate::problem::{Contact, ContactFace, Inertia, NoQuadrature, Probe, Problem};
use nalgebra::DMatrix;

/// A point mass on a spring.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointMass {
    /// m > 0.
    pub mass: f64,
    /// k ≥ 0.
    pub stiffness: f64,
}

/// The initial state and load of a point mass.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointInitial {
    /// u₀ ≥ 0.
    pub displacement: f64,
    /// v₀.
    pub velocity: f64,
    /// The constant force f.
    pub load: f64,
    /// The constant that makes the energy the physical one (the spring's energy at u = 0).
    pub energy_shift: f64,
}

impl PointMass {
    /// The element data: the mass m on the single (contact) dof.
    pub fn mass_model(&self) -> MassModel {
        MassModel {
            n_dofs: 1,
            dim: 1,
            elements: vec![ElementMass {
                x: vec![[0.0; 3]],
                mass: DMatrix::from_element(1, 1, self.mass),
                dofs: vec![vec![Some(0)]],
            }],
            contact_dofs: vec![0],
            velocity: None,
        }
    }

    /// The semi-discrete problem with the inertia a space builds from [`PointMass::mass_model`].
    pub fn problem(
        &self,
        inertia: impl FnOnce(&MassModel) -> Result<Box<dyn Inertia>>,
        initial: &PointInitial,
    ) -> Result<Problem> {
        let mut k = TripletBuilder::new(1, 1);
        k.add(0, 0, self.stiffness);
        let mut b_n = TripletBuilder::new(1, 1);
        b_n.add(0, 0, -1.0);
        Ok(Problem {
            inertia: inertia(&self.mass_model())?,
            k: k.build()?,
            f: vec![initial.load],
            contact: Contact {
                b_n: b_n.build()?,
                g0: vec![0.0],
                area: vec![1.0],
                faces: vec![ContactFace::point(0)],
                vertices: None,
                quadrature: Err(NoQuadrature::PointMass),
                force: None,
                normal: None,
                energy: Vec::new(),
                friction: None,
            },
            u0: vec![initial.displacement],
            v0: vec![initial.velocity],
            probe: Probe {
                contact: 0,
                u_dof: 0,
                w_dof: 0,
            },
            energy_shift: initial.energy_shift,
        })
    }
}
