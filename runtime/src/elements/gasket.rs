//! Door gasket: 6-D linear spring-damper with full (non-diagonal) K and D in global axes at the
//! gasket point, zero force in the reference position (seed paper: K from a static FE analysis
//! of the rubber, D fitted).

use super::Element;
use crate::equations::{Marker, MarkerDef, Wrench};
use crate::geom::V;
use crate::ir;
use crate::scalar::Scalar;

#[derive(Clone, Debug, PartialEq)]
pub struct Gasket {
    pub name: String,
    pub a: MarkerDef,
    pub b: MarkerDef,
    pub stiffness: [[f64; 6]; 6],
    /// `None` when the scene leaves gasket damping out.
    pub damping: Option<[[f64; 6]; 6]>,
}

impl Gasket {
    pub fn new(g: &ir::Gasket, a: MarkerDef, b: MarkerDef, with_damping: bool) -> Self {
        Gasket {
            name: g.name.clone(),
            a,
            b,
            stiffness: g.stiffness,
            damping: with_damping.then_some(g.damping),
        }
    }
}

impl Element for Gasket {
    fn markers(&self) -> (&MarkerDef, &MarkerDef) {
        (&self.a, &self.b)
    }

    /// Wrench on a: -K x - D x', x = displacement and rotation of a relative to b. Linear in
    /// either geometry.
    fn wrenches<T: Scalar>(
        &self,
        a: &Marker<T>,
        b: &Marker<T>,
        _exact: bool,
    ) -> (Wrench<T>, Wrench<T>) {
        let dx = a.pos - b.pos - (V::c(self.a.point) - V::c(self.b.point));
        let x = [dx.0, (a.rot - b.rot).0].concat_arr();
        let xd = [(a.vel - b.vel).0, (a.angvel - b.angvel).0].concat_arr();
        let mut w = [T::zero(); 6];
        for (i, wi) in w.iter_mut().enumerate() {
            for j in 0..6 {
                *wi -= x[j] * self.stiffness[i][j];
                if let Some(d) = &self.damping {
                    *wi -= xd[j] * d[i][j];
                }
            }
        }
        let wa = Wrench {
            force: V([w[0], w[1], w[2]]),
            moment: V([w[3], w[4], w[5]]),
        };
        // Both markers sit at the same point, so b takes the plain reaction.
        (wa, wa.reaction())
    }
}

trait Concat<T> {
    fn concat_arr(self) -> [T; 6];
}

impl<T: Copy> Concat<T> for [[T; 3]; 2] {
    fn concat_arr(self) -> [T; 6] {
        let [a, b] = self;
        [a[0], a[1], a[2], b[0], b[1], b[2]]
    }
}
