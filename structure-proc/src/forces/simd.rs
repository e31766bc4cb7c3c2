//! The force pass's hot loops in AVX2, four f64 lanes at a time (springs,
//! membrane triangles, dampers of thesis eq. 68, and the node sums), taken
//! where the CPU has AVX2 (every x86-64 CPU since 2013–2015); elsewhere each
//! function returns `false` and its caller runs the scalar loop.
//!
//! Every kernel does the scalar loops' arithmetic in the scalar loops' order,
//! lane by lane: IEEE 754 rounds a vector add, multiply, divide and square
//! root exactly as it rounds the scalar ones, and Rust contracts no multiply
//! and add into a fused one. So the force is the same bits with or without
//! AVX2 and on any number of threads (tested in `spring_batch.rs`,
//! `membrane_batch.rs`, `damper_batch.rs` and `structure-proc/tests/forces.rs`).
//!
//! Why by hand: the compiler vectorises the springs' arithmetic but not the
//! gathers of their end points, which it turns into scalar loads and
//! shuffles. Here each end point is one masked 256-bit load of (x, y, z), four
//! differences are transposed into x, y and z vectors for the length and
//! tension, and each spring's force is stored as one padded slot. A
//! triangle's three edges and a damper's two end velocities go the same way.

use super::assembly::{Assembly, Slot};
use super::damper_batch::DamperBatch;
use super::damping::Law;
use super::membrane_batch::MembraneBatch;
use super::spring_batch::SpringBatch;

/// out[t] ← the force on node i of spring t, for every slot of
/// `out`, as [`crate::Spring::force`] computes it; `false` (nothing written)
/// without AVX2.
pub fn spring_forces(springs: &SpringBatch, x: &[f64], out: &mut [Slot]) -> bool {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        assert!(out.len() <= springs.len() && 3 * springs.nodes() <= x.len());
        // SAFETY: AVX2 is present; the assert and SpringBatch::new (every end
        // below `nodes`) keep every read inside `springs` and `x`.
        unsafe { avx2::spring_forces(springs, x, out) };
        return true;
    }
    let _ = (springs, x, out);
    false
}

/// out[3k + e] ← the force of triangle `first + k`'s edge e, for every
/// slot of `out`, as [`crate::forces::delingette::TriangleSprings::edge_forces`]
/// computes it; `false` (nothing written) without AVX2.
pub fn membrane_forces(b: &MembraneBatch, x: &[f64], first: usize, out: &mut [Slot]) -> bool {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        assert!(out.len().is_multiple_of(3) && first + out.len() / 3 <= b.len());
        assert!(3 * b.nodes() <= x.len());
        // SAFETY: AVX2 is present; the asserts and MembraneBatch::new (every
        // vertex below `nodes`) keep every read inside `b` and `x`.
        unsafe { avx2::membrane_forces(b, x, first, out) };
        return true;
    }
    let _ = (b, x, first, out);
    false
}

/// out[k] ← the force of damper `first + k` under thesis eq. (68)'s law,
/// for every slot of `out`, as [`crate::forces::damping::Damper::force`]
/// computes it; `false` (nothing written) without AVX2 or for the axial law.
pub fn damper_forces(
    b: &DamperBatch,
    law: Law,
    x: &[f64],
    v: &[f64],
    first: usize,
    out: &mut [Slot],
) -> bool {
    #[cfg(target_arch = "x86_64")]
    if law == Law::RelativeVelocity && std::arch::is_x86_feature_detected!("avx2") {
        assert!(first + out.len() <= b.len() && 3 * b.nodes() <= x.len().min(v.len()));
        // SAFETY: AVX2 is present; the assert and DamperBatch::new (every
        // end below `nodes`) keep every read inside `b`, `x` and `v`.
        unsafe { avx2::relative_velocity(b, x, v, first, out) };
        return true;
    }
    let _ = (b, law, x, v, first, out);
    false
}

/// out[3k..3k+3] ← Σ ± slots of node `first + k` on top of
/// `init(first + k, out[3k..3k+3])`, adding the slots in the order of the
/// node's entries, as [`Assembly`]'s scalar loop does; `false` (nothing
/// written) without AVX2.
pub fn sum_nodes(
    assembly: &Assembly,
    slots: &[Slot],
    first: usize,
    out: &mut [f64],
    init: &impl Fn(usize, &[f64]) -> Slot,
) -> bool {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        assert!(out.len().is_multiple_of(3) && first + out.len() / 3 <= assembly.nodes());
        assert_eq!(slots.len(), assembly.slots());
        // SAFETY: AVX2 is present; Assembly::new keeps its starts
        // non-decreasing and within its entries, and every entry's slot below
        // its slot count, which is `slots.len()`.
        unsafe { avx2::sum_nodes(&assembly.start, &assembly.entries, slots, first, out, init) };
        return true;
    }
    let _ = (assembly, slots, first, out, init);
    false
}

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use super::{DamperBatch, Law, MembraneBatch, Slot, SpringBatch};
    use std::arch::x86_64::*;

    /// Lanes x, y, z of a node's three values.
    #[inline(always)]
    unsafe fn xyz() -> __m256i {
        _mm256_setr_epi64x(-1, -1, -1, 0)
    }

    /// The differences x_j − x_i of elements g..g + 4 with ends `i` and
    /// `j` (springs' or dampers'), as (x, y, z, 0); `x` may be positions or
    /// velocities.
    #[inline(always)]
    unsafe fn differences(i: &[u32], j: &[u32], x: &[f64], g: usize) -> [__m256d; 4] {
        let at = |n: u32| x.as_ptr().add(3 * n as usize);
        std::array::from_fn(|k| {
            let a = _mm256_maskload_pd(at(*i.get_unchecked(g + k)), xyz());
            let b = _mm256_maskload_pd(at(*j.get_unchecked(g + k)), xyz());
            _mm256_sub_pd(b, a)
        })
    }

    /// The lengths of four (x, y, z, 0) vectors, √((x² + y²) + z²) as
    /// nalgebra's `norm` rounds it.
    #[inline(always)]
    unsafe fn lengths(d: &[__m256d; 4]) -> __m256d {
        _mm256_sqrt_pd(squared_lengths(d))
    }

    /// Their squares (x² + y²) + z², as nalgebra's `norm_squared` rounds them.
    #[inline(always)]
    unsafe fn squared_lengths(d: &[__m256d; 4]) -> __m256d {
        let lo01 = _mm256_unpacklo_pd(d[0], d[1]); // x0 x1 z0 z1
        let hi01 = _mm256_unpackhi_pd(d[0], d[1]); // y0 y1 0 0
        let lo23 = _mm256_unpacklo_pd(d[2], d[3]);
        let hi23 = _mm256_unpackhi_pd(d[2], d[3]);
        let dx = _mm256_permute2f128_pd(lo01, lo23, 0x20);
        let dy = _mm256_permute2f128_pd(hi01, hi23, 0x20);
        let dz = _mm256_permute2f128_pd(lo01, lo23, 0x31);
        let sq = |v| _mm256_mul_pd(v, v);
        _mm256_add_pd(_mm256_add_pd(sq(dx), sq(dy)), sq(dz))
    }

    /// Lane k of `v` in every lane.
    #[inline(always)]
    unsafe fn lane(v: __m256d, k: usize) -> __m256d {
        match k {
            0 => _mm256_permute4x64_pd(v, 0x00),
            1 => _mm256_permute4x64_pd(v, 0x55),
            2 => _mm256_permute4x64_pd(v, 0xAA),
            _ => _mm256_permute4x64_pd(v, 0xFF),
        }
    }

    /// Tension per unit length k·δ/l of four springs whose differences are
    /// `d`, 0 where l = 0 (Spring::force: δ = l − l⁰ for a spring,
    /// max(l − l⁰ − ε, 0) for a string).
    #[inline(always)]
    unsafe fn per_length(s: &SpringBatch, d: &[__m256d; 4], g: usize) -> __m256d {
        let l = lengths(d);
        let load = |v: &[f64]| _mm256_loadu_pd(v.as_ptr().add(g));
        let mut stretch = _mm256_sub_pd(l, load(&s.rest));
        if s.strings {
            // max_pd(a, b) is b when b is NaN, as f64::max would not be; a
            // NaN comes only from a NaN length, whose lane the l > 0 mask zeroes.
            let over = _mm256_sub_pd(stretch, load(&s.eps));
            stretch = _mm256_max_pd(_mm256_setzero_pd(), over);
        }
        let q = _mm256_div_pd(_mm256_mul_pd(load(&s.k), stretch), l);
        _mm256_and_pd(_mm256_cmp_pd(l, _mm256_setzero_pd(), _CMP_GT_OQ), q)
    }

    #[target_feature(enable = "avx2")]
    pub unsafe fn spring_forces(s: &SpringBatch, x: &[f64], out: &mut [Slot]) {
        let whole = out.len() / 4 * 4;
        for t in (0..whole).step_by(4) {
            let d = differences(&s.i, &s.j, x, t);
            let p = per_length(s, &d, t);
            let o = out.as_mut_ptr().add(t) as *mut f64;
            _mm256_store_pd(o, _mm256_mul_pd(d[0], _mm256_permute4x64_pd(p, 0x00)));
            _mm256_store_pd(
                o.add(4),
                _mm256_mul_pd(d[1], _mm256_permute4x64_pd(p, 0x55)),
            );
            _mm256_store_pd(
                o.add(8),
                _mm256_mul_pd(d[2], _mm256_permute4x64_pd(p, 0xAA)),
            );
            _mm256_store_pd(
                o.add(12),
                _mm256_mul_pd(d[3], _mm256_permute4x64_pd(p, 0xFF)),
            );
        }
        for (t, o) in out.iter_mut().enumerate().skip(whole) {
            *o = s.scalar_force(x, t);
        }
    }

    /// Four triangles at a time: the edge vectors d_e = p_b − p_a as
    /// (x, y, z, 0), their lengths, dl = l − l⁰, the tensions
    /// T = Q·dl summed ((Q_e0 dl_0 + Q_e1 dl_1) + Q_e2 dl_2) as nalgebra's
    /// product does, and each edge's force d_e·(T_e/l_e) (its fourth lane
    /// kept zero).
    #[target_feature(enable = "avx2")]
    pub unsafe fn membrane_forces(b: &MembraneBatch, x: &[f64], first: usize, out: &mut [Slot]) {
        let count = out.len() / 3;
        let whole = count / 4 * 4;
        let at = |n: u32| x.as_ptr().add(3 * n as usize);
        let keep_xyz = _mm256_castsi256_pd(xyz());
        for g in (0..whole).step_by(4) {
            let t = first + g;
            let p: [[__m256d; 4]; 3] = std::array::from_fn(|v| {
                std::array::from_fn(|k| {
                    _mm256_maskload_pd(at(*b.nodes[v].get_unchecked(t + k)), xyz())
                })
            });
            // Edge e runs from vertex e to vertex e + 1 (delingette.rs's EDGES).
            let d: [[__m256d; 4]; 3] = std::array::from_fn(|e| {
                std::array::from_fn(|k| _mm256_sub_pd(p[(e + 1) % 3][k], p[e][k]))
            });
            let load = |v: &[f64]| _mm256_loadu_pd(v.as_ptr().add(t));
            let l: [__m256d; 3] = std::array::from_fn(|e| lengths(&d[e]));
            let dl: [__m256d; 3] = std::array::from_fn(|e| _mm256_sub_pd(l[e], load(&b.rest[e])));
            let per_length: [__m256d; 3] = std::array::from_fn(|e| {
                let q = |f: usize| _mm256_mul_pd(load(&b.q[3 * e + f]), dl[f]);
                let tension = _mm256_add_pd(_mm256_add_pd(q(0), q(1)), q(2));
                _mm256_div_pd(tension, l[e])
            });
            let o = out.as_mut_ptr().add(3 * g) as *mut f64;
            for k in 0..4 {
                for e in 0..3 {
                    let f = _mm256_mul_pd(d[e][k], lane(per_length[e], k));
                    _mm256_store_pd(o.add(4 * (3 * k + e)), _mm256_and_pd(f, keep_xyz));
                }
            }
        }
        for k in whole..count {
            let o = &mut out[3 * k..3 * k + 3];
            o.copy_from_slice(&b.scalar_forces(x, first + k));
        }
    }

    /// Four dampers at a time: c·(v_j − v_i) where the ends' distance l
    /// is above zero and above the slack length (l² > 0 alone where that
    /// is zero, as Damper::acts decides), zero elsewhere.
    #[target_feature(enable = "avx2")]
    pub unsafe fn relative_velocity(
        b: &DamperBatch,
        x: &[f64],
        v: &[f64],
        first: usize,
        out: &mut [Slot],
    ) {
        let whole = out.len() / 4 * 4;
        let zero = _mm256_setzero_pd();
        let keep_xyz = _mm256_castsi256_pd(xyz());
        for g in (0..whole).step_by(4) {
            let t = first + g;
            let d = differences(&b.i, &b.j, x, t);
            let dv = differences(&b.i, &b.j, v, t);
            let squared = squared_lengths(&d);
            let slack = _mm256_loadu_pd(b.slack_below.as_ptr().add(t));
            // Damper::acts: l² > 0, and √(l²) > slack unless slack = 0.
            let beyond = _mm256_or_pd(
                _mm256_cmp_pd(slack, zero, _CMP_EQ_OQ),
                _mm256_cmp_pd(_mm256_sqrt_pd(squared), slack, _CMP_GT_OQ),
            );
            let acts = _mm256_and_pd(_mm256_cmp_pd(squared, zero, _CMP_GT_OQ), beyond);
            let c = _mm256_loadu_pd(b.c.as_ptr().add(t));
            let o = out.as_mut_ptr().add(g) as *mut f64;
            for k in 0..4 {
                let f = _mm256_mul_pd(dv[k], lane(c, k));
                // Zero where the damper idles, and in the fourth lane.
                let on = _mm256_and_pd(lane(acts, k), keep_xyz);
                _mm256_store_pd(o.add(4 * k), _mm256_and_pd(f, on));
            }
        }
        for (k, o) in out.iter_mut().enumerate().skip(whole) {
            *o = b.scalar_force(Law::RelativeVelocity, x, v, first + k);
        }
    }

    #[target_feature(enable = "avx2")]
    pub unsafe fn sum_nodes(
        start: &[usize],
        entries: &[u32],
        slots: &[Slot],
        first: usize,
        out: &mut [f64],
        init: &impl Fn(usize, &[f64]) -> Slot,
    ) {
        // a − s is a + (−s) in IEEE 754: flipping the sign bit subtracts.
        let sign = [_mm256_setzero_pd(), _mm256_set1_pd(-0.0)];
        let slot = slots.as_ptr() as *const f64;
        for (k, o) in out.chunks_exact_mut(3).enumerate() {
            let n = first + k;
            let mut sum = _mm256_load_pd(init(n, o).0.as_ptr());
            let (lo, hi) = (*start.get_unchecked(n), *start.get_unchecked(n + 1));
            for &e in entries.get_unchecked(lo..hi) {
                let s = _mm256_load_pd(slot.add(4 * (e >> 1) as usize));
                sum = _mm256_add_pd(sum, _mm256_xor_pd(s, sign[(e & 1) as usize]));
            }
            let mut lanes = Slot::ZERO;
            _mm256_store_pd(lanes.0.as_mut_ptr(), sum);
            o.copy_from_slice(&lanes.0[..3]);
        }
    }
}
