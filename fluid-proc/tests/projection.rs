//! The projection of dissertation eq. (3.19) on the MAC grid: a velocity field
//! with arbitrary divergence leaves it divergence-free to 1e-10 relative
//! (the Deliver bound of issue 6), keeps the velocities the sides impose,
//! and projecting again changes nothing (a projection is idempotent).

use fluid_proc::incompressible::faces::{divergence, Faces};
use fluid_proc::incompressible::grid::{Bc, Grid};
use fluid_proc::incompressible::poisson::Poisson;
use fluid_proc::incompressible::projection::project;

/// Uniform numbers in [−1, 1) from a fixed seed (a 64-bit LCG, Knuth's MMIX constants).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// A grid of `n` cells over a box of 1 m (2-D: one cell thick, periodic in z)
/// and a random field obeying its sides: zero normal velocity on walls,
/// 1 m/s ± 10 % up through a Neumann floor under a Dirichlet top (inflow,
/// outflow), equal periodic faces.
fn case(n: [usize; 3], bc: [[Bc; 2]; 3], seed: u64) -> (Grid, Faces) {
    let g = Grid::uniform(n, [1.0 / n[0] as f64; 3], bc);
    let mut u = Faces::zeros(&g);
    let mut rng = Lcg(seed);
    for d in 0..3 {
        for f in 0..u.u[d].len() {
            u.u[d][f] = rng.next();
        }
        for f in 0..u.u[d].len() {
            let Some((s, twin)) = side(n, d, f) else {
                continue;
            };
            u.u[d][f] = match (bc[d][s], bc[d][1 - s]) {
                // Face n repeats face 0.
                (Bc::Periodic, _) => u.u[d][twin],
                (Bc::Neumann, Bc::Dirichlet) => 1.0 + 0.1 * rng.next(),
                (Bc::Neumann, _) => 0.0,
                (Bc::Dirichlet, _) => u.u[d][f],
                (Bc::Rank, _) => unreachable!("one rank"),
            };
        }
    }
    (g, u)
}

/// For a face normal to d on a side of the box: which side (0 low, 1 high)
/// and the index of the face on the opposite side of its row.
fn side(n: [usize; 3], d: usize, f: usize) -> Option<(usize, usize)> {
    let mut m = n;
    m[d] += 1;
    let stride = [1, m[0], m[0] * m[1]][d];
    match (f / stride) % m[d] {
        0 => Some((0, f + n[d] * stride)),
        k if k == n[d] => Some((1, f - n[d] * stride)),
        _ => None,
    }
}

fn relative_divergence(g: &Grid, u: &Faces) -> f64 {
    let mut div = vec![0.0; g.cells()];
    divergence(g, u, &mut div);
    div.iter().fold(0.0f64, |m, v| m.max(v.abs())) * g.h[0] / u.max_abs()
}

#[test]
fn projected_fields_are_divergence_free_and_keep_their_boundary_velocities() {
    let walls = [[Bc::Neumann; 2], [Bc::Neumann; 2], [Bc::Periodic; 2]];
    let c9_2d = [
        [Bc::Periodic; 2],
        [Bc::Neumann, Bc::Dirichlet],
        [Bc::Periodic; 2],
    ];
    let c9_3d = [
        [Bc::Periodic; 2],
        [Bc::Periodic; 2],
        [Bc::Neumann, Bc::Dirichlet],
    ];
    let box3 = [[Bc::Neumann; 2]; 3];
    let cases = [
        ("cavity 2-D", [64, 64, 1], walls),
        ("C-9 2-D", [64, 64, 1], c9_2d),
        ("C-9 3-D", [24, 24, 24], c9_3d),
        ("closed box 3-D", [24, 24, 24], box3),
    ];
    for (k, (name, n, bc)) in cases.into_iter().enumerate() {
        let (g, mut u) = case(n, bc, 7 + k as u64);
        let before = u.clone();
        assert!(
            relative_divergence(&g, &u) > 0.1,
            "{name}: the test field is already solenoidal"
        );
        let mut poisson = Poisson::new(&g, 1e-13);
        let (mut phi, mut scratch) = (vec![0.0; g.cells()], vec![0.0; g.cells()]);
        let dt = 1e-2;
        project(&g, &mut poisson, &mut u, dt, &mut phi, &mut scratch).unwrap();
        let rel = relative_divergence(&g, &u);
        assert!(rel < 1e-10, "{name}: divergence {rel:e} after projection");
        // The sides' given velocities stay: walls and inflow untouched.
        for d in 0..3 {
            for f in 0..u.u[d].len() {
                let Some((s, twin)) = side(n, d, f) else {
                    continue;
                };
                if bc[d][s] == Bc::Neumann {
                    assert_eq!(
                        u.u[d][f], before.u[d][f],
                        "{name}: a given face velocity moved"
                    );
                }
                if bc[d][s] == Bc::Periodic {
                    assert_eq!(u.u[d][f], u.u[d][twin], "{name}: periodic faces differ");
                }
            }
        }
        // Idempotent: a second projection changes nothing.
        let once = u.clone();
        project(&g, &mut poisson, &mut u, dt, &mut phi, &mut scratch).unwrap();
        let change = (0..3)
            .flat_map(|d| u.u[d].iter().zip(&once.u[d]).map(|(a, b)| (a - b).abs()))
            .fold(0.0, f64::max);
        assert!(
            change < 1e-10 * u.max_abs(),
            "{name}: second projection moved u by {change:e}"
        );
    }
}
