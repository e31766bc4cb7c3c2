//! Mass properties (dissertation §2.1): mass, centre of mass, the inertia tensor
//! of eq. (2.6) about the centre, and its eigen-decomposition I = QΛQᵀ of
//! eq. (2.7) into principal moments and principal axes.

use crate::shape::Shape;
use nalgebra::{Matrix3, SymmetricEigen, Vector3};

#[derive(Debug, Clone, PartialEq)]
pub struct MassProperties {
    /// [kg]
    pub mass: f64,
    /// Centre of mass in the body's own frame [m].
    pub centre: Vector3<f64>,
    /// Inertia tensor about the centre of mass, own axes [kg·m²] (eq. 2.6).
    pub inertia: Matrix3<f64>,
    /// Principal moments I₁ ≤ I₂ ≤ I₃ [kg·m²] (eq. 2.7).
    pub principal: Vector3<f64>,
    /// Principal axes as the columns of a proper rotation Q (det Q = +1):
    /// own-frame vector = Q · principal-frame vector.
    pub axes: Matrix3<f64>,
}

impl MassProperties {
    /// A mass point: no extent, no rotational inertia.
    pub fn point(mass: f64) -> MassProperties {
        MassProperties::from_tensor(mass, Vector3::zeros(), Matrix3::zeros())
    }

    /// A shape of uniform `density` [kg/m³]. parry integrates eq. (2.6) over
    /// the solid (for a mesh, over the tetrahedra its faces span with the
    /// centre); the decomposition is ours, so the moments come sorted.
    pub fn of_shape(shape: &Shape, density: f64) -> MassProperties {
        let p = shape
            .shape
            .mass_properties(density)
            .transform_by(&shape.placement);
        MassProperties::from_tensor(p.mass(), p.local_com.coords, p.reconstruct_inertia_matrix())
    }

    /// Principal moments and axes of a symmetric inertia tensor (eq. 2.7).
    pub fn from_tensor(mass: f64, centre: Vector3<f64>, inertia: Matrix3<f64>) -> MassProperties {
        let inertia = (inertia + inertia.transpose()) / 2.0;
        let eigen = SymmetricEigen::new(inertia);
        let mut order = [0, 1, 2];
        order.sort_by(|&a, &b| eigen.eigenvalues[a].total_cmp(&eigen.eigenvalues[b]));
        let principal = Vector3::from_fn(|i, _| eigen.eigenvalues[order[i]].max(0.0));
        let mut axes = Matrix3::from_fn(|r, c| eigen.eigenvectors[(r, order[c])]);
        if axes.determinant() < 0.0 {
            // A reflection is no orientation: flip the third axis.
            axes.set_column(2, &-axes.column(2));
        }
        MassProperties {
            mass,
            centre,
            inertia,
            principal,
            axes,
        }
    }
}
