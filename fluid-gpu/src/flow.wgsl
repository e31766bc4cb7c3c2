// The incompressible step of dissertation §3.2.2 on the device, pass for
// pass the CPU path's (fluid-proc's incompressible/): WENO5 advection in
// flux form with Adams–Bashforth, the Crank–Nicolson viscous solve by
// conjugate gradients, the projection with a multigrid-preconditioned
// conjugate-gradient Poisson solve, and the pressure update of eq. (3.20).
//
// The host prepends `alias real = f64;` (or f32), the box's constants
// (NC cells, GH ghost layers per axis, the sides' kinds SIDE, the velocity
// arrays' offsets U_OFF, the cell arrays' Q_OFF and PHI_OFF, the multigrid
// levels' cells LEVEL_N, SINGULAR) and the scalar slots. Every array lives
// in `f`: a velocity component on its faces with three ghost layers per
// side as fluid-proc's `Padded`, cell fields x fastest. Every scalar (the
// step's Δt, the solves' sums and flags) lives in `s`, so that a solve's
// iterations run without the host. Each dispatch reads its arrays, its box
// and its flags from `op` (a dynamic offset into one uniform buffer).

struct Op {
    o0: u32, o1: u32, o2: u32, o3: u32,
    // The box of entries the pass runs over: its low corner (padded
    // coordinates), its extents, the strides of the array it indexes.
    lo0: u32, lo1: u32, lo2: u32, kind: u32,
    e0: u32, e1: u32, e2: u32, comp: u32,
    s0: u32, s1: u32, s2: u32, aux: u32,
    // A scalar slot; the solve's block of slots; 1: skip once the solve
    // is done, 2: run only where its right-hand side was zero; a count.
    slot: u32, solve: u32, guard: u32, count: u32,
}

// The arrays, in up to four bindings (an adapter binds a limited size
// each): entry i of the whole lies in f0 below SEG1, in f1 below SEG2, …
@group(0) @binding(0) var<storage, read_write> f0: array<real>;
@group(0) @binding(6) var<storage, read_write> f1: array<real>;
@group(0) @binding(7) var<storage, read_write> f2: array<real>;
@group(0) @binding(8) var<storage, read_write> f3: array<real>;
@group(0) @binding(1) var<storage, read_write> s: array<real>;
@group(0) @binding(2) var<storage, read_write> part: array<real>;
@group(0) @binding(3) var<uniform> op: Op;
// The markers of the bodies and the canopy in the flow, MARKER reals each
// (`markers.rs`), and the blocks they are sorted into: (first, end) pairs,
// colour after colour.
@group(0) @binding(4) var<storage, read_write> mk: array<real>;
@group(0) @binding(5) var<storage, read> blocks: array<u32>;

const WG: u32 = 256u;

// Entry i of the arrays, and its update.
fn rd(i: u32) -> real {
    if i < SEG1 {
        return f0[i];
    }
    if i < SEG2 {
        return f1[i - SEG1];
    }
    if i < SEG3 {
        return f2[i - SEG2];
    }
    return f3[i - SEG3];
}

fn wr(i: u32, v: real) {
    if i < SEG1 {
        f0[i] = v;
    } else if i < SEG2 {
        f1[i - SEG1] = v;
    } else if i < SEG3 {
        f2[i - SEG2] = v;
    } else {
        f3[i - SEG3] = v;
    }
}

fn rdi(i: i32) -> real {
    return rd(u32(i));
}

fn wri(i: i32, v: real) {
    wr(u32(i), v);
}
// Side kinds (fluid-gpu's `Side`).
const GIVEN: u32 = 0u;
const OUTFLOW: u32 = 1u;
const PERIODIC: u32 = 2u;
const PARABOLIC: u32 = 3u;
// A solve's block of scalar slots.
const DONE: u32 = 0u;
const ITER: u32 = 1u;
const RR: u32 = 2u;
const PQ: u32 = 3u;
const STEP: u32 = 4u;
const BETA: u32 = 5u;
const GOAL: u32 = 6u;
const RRN: u32 = 7u;
const RZ: u32 = 8u;
const RZN: u32 = 9u;
const BB: u32 = 10u;
const MEANB: u32 = 11u;
const FAIL: u32 = 12u;
const SCALE: u32 = 13u;

var<workgroup> shared_sum: array<real, WG>;
var<workgroup> shared_flag: u32;

fn thread(gid: vec3<u32>, groups: vec3<u32>) -> u32 {
    return gid.x + gid.y * groups.x * WG;
}

// Whether this pass is skipped: its solve is done (guard 1), or its
// right-hand side was not zero (guard 2).
fn skipped() -> bool {
    let done = s[op.solve + DONE];
    return (op.guard == 1u && done != 0.0) || (op.guard == 2u && done != 2.0);
}

// The padded coordinates of thread t of the op's box, and whether it is in it.
fn box_coords(t: u32) -> vec3<u32> {
    let i = t % op.e0;
    let j = (t / op.e0) % op.e1;
    let k = t / (op.e0 * op.e1);
    return vec3<u32>(op.lo0 + i, op.lo1 + j, op.lo2 + k);
}

fn box_size() -> u32 {
    return op.e0 * op.e1 * op.e2;
}

fn box_index(q: vec3<u32>) -> u32 {
    return q.x * op.s0 + q.y * op.s1 + q.z * op.s2;
}

fn is_finite(x: real) -> bool {
    return abs(x) <= s[HUGE];
}

// ---- Layouts ----------------------------------------------------------

// Component c's padded array: n + 1 faces along c, n cells elsewhere,
// GH ghosts each side.
fn cdims(c: u32) -> vec3<u32> {
    var m = NC;
    m[c] += 1u;
    return m + 2u * GH;
}

fn cstride(c: u32) -> vec3<u32> {
    let d = cdims(c);
    return vec3<u32>(1u, d.x, d.x * d.y);
}

// Index in component c's array of face `q` (unpadded face coordinates).
fn at(c: u32, q: vec3<i32>) -> u32 {
    let p = vec3<u32>(q + vec3<i32>(GH));
    let st = cstride(c);
    return U_OFF[c] + p.x * st.x + p.y * st.y + p.z * st.z;
}

fn unit(a: u32) -> vec3<i32> {
    var e = vec3<i32>(0, 0, 0);
    e[a] = 1;
    return e;
}

fn cell_index(n: vec3<u32>, c: vec3<u32>) -> u32 {
    return c.x + n.x * (c.y + n.y * c.z);
}

fn cell_coords(n: vec3<u32>, t: u32) -> vec3<u32> {
    return vec3<u32>(t % n.x, (t / n.x) % n.y, t / (n.x * n.y));
}

// ---- Sides --------------------------------------------------------------

// ∂φ/∂x_d on face `q` normal to d of the cell field at `off` (fluid-proc's
// `projection::gradient`): a plain difference inside; across a periodic
// side the cells at both ends; on an outflow φ = 0 on the face, half a
// cell away; on a side of given velocity zero, so that velocity stays.
fn face_gradient(off: u32, d: u32, q: vec3<i32>) -> real {
    let n = i32(NC[d]);
    let k = q[d];
    let inv_h = s[INV_H + d];
    var lo = vec3<u32>(q);
    var hi = vec3<u32>(q);
    if k > 0 && k < n {
        lo[d] = u32(k - 1);
        return (rd(off + cell_index(NC, hi)) - rd(off + cell_index(NC, lo))) * inv_h;
    }
    let side = SIDE[2u * d + select(0u, 1u, k == n)];
    lo[d] = 0u;
    hi[d] = u32(n - 1);
    if side == PERIODIC {
        return (rd(off + cell_index(NC, lo)) - rd(off + cell_index(NC, hi))) * inv_h;
    }
    if side == OUTFLOW {
        if k == 0 {
            return 2.0 * rd(off + cell_index(NC, lo)) * inv_h;
        }
        return -2.0 * rd(off + cell_index(NC, hi)) * inv_h;
    }
    return 0.0;
}

// The ghosts of one line along axis `op.aux` of component `op.comp`'s array
// at `op.o0` (fluid-proc's `Padded::fill_line`), the sides' velocities
// from slot `op.slot` on (SIDE_U or SIDE_END); `op.kind` 1: the
// homogeneous sides of a correction (given velocities zero).
@compute @workgroup_size(256)
fn ghosts(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = thread(gid, groups);
    if t >= op.count || skipped() {
        return;
    }
    let c = op.comp;
    let a = op.aux;
    let dims = cdims(c);
    let st = cstride(c);
    let b = (a + 1u) % 3u;
    let e = (a + 2u) % 3u;
    let base = i32(op.o0 + (t % dims[b]) * st[b] + (t / dims[b]) * st[e] + GH[a] * st[a]);
    let g = i32(GH[a]);
    let m = i32(dims[a]) - 2 * g;
    let sa = i32(st[a]);
    let last = m - 1;
    let normal = a == c;
    let low = SIDE[2u * a];
    if low == PERIODIC {
        let period = select(m, m - 1, normal);
        if normal {
            wri(base + last * sa, rdi(base));
        }
        for (var k = 1; k <= g; k++) {
            wri(base - k * sa, rdi(base + (period - k) * sa));
            wri(base + (last + k) * sa, rdi(base + (last - period + k) * sa));
        }
        return;
    }
    let lines = vec3<u32>(0u, t % dims[b], t / dims[b]);
    for (var up = 0u; up < 2u; up++) {
        let side = SIDE[2u * a + up];
        let edge = select(0, last, up == 1u);
        let dir = select(-1, 1, up == 1u);
        if side == GIVEN || side == PARABOLIC {
            var given = select(s[op.slot + 3u * (2u * a + up) + c], 0.0, op.kind == 1u);
            if side == PARABOLIC {
                given *= profile(c, a, lines);
            }
            if normal {
                wri(base + edge * sa, given);
                for (var k = 1; k <= g; k++) {
                    wri(base + (edge + dir * k) * sa, 2.0 * given - rdi(base + (edge - dir * k) * sa));
                }
            } else {
                for (var k = 1; k <= g; k++) {
                    wri(base + (edge + dir * k) * sa, 2.0 * given - rdi(base + (edge - dir * (k - 1)) * sa));
                }
            }
        } else if side == OUTFLOW {
            for (var k = 1; k <= g; k++) {
                wri(base + (edge + dir * k) * sa, rdi(base + edge * sa));
            }
        }
    }
}

// The shape factor of a parabolic side normal to a for the line of
// component c whose padded places along the other two axes b = a + 1 and
// e = a + 2 are lines.y and lines.z (fluid-proc's `Padded::profile`):
// Poiseuille's 4s(1 − s) across each of them that is not periodic, s from
// 0 at one wall to 1 at the other; a ghost line beyond a wall takes 0.
fn profile(c: u32, a: u32, lines: vec3<u32>) -> real {
    var f: real = 1.0;
    for (var k = 1u; k < 3u; k++) {
        let t = (a + k) % 3u;
        if SIDE[2u * t] == PERIODIC {
            continue;
        }
        let i = real(i32(lines[k]) - i32(GH[t]));
        var s: real;
        if t == c {
            s = i / real(NC[t]);
        } else {
            s = (i + 0.5) / real(NC[t]);
        }
        s = clamp(s, 0.0, 1.0);
        f *= 4.0 * s * (1.0 - s);
    }
    return f;
}

// ---- Advection and the viscous term -------------------------------------

// Fifth-order WENO (Jiang & Shu 1996; fluid-proc's weno5.rs): the value at
// i+½ from the five values i−2…i+2, upwind from the left.
fn weno(a: real, b: real, c: real, d: real, e: real) -> real {
    let q0 = (2.0 * a - 7.0 * b + 11.0 * c) / 6.0;
    let q1 = (-b + 5.0 * c + 2.0 * d) / 6.0;
    let q2 = (2.0 * c + 5.0 * d - e) / 6.0;
    let t0 = a - 2.0 * b + c;
    let u0 = a - 4.0 * b + 3.0 * c;
    let t1 = b - 2.0 * c + d;
    let u1 = b - d;
    let t2 = c - 2.0 * d + e;
    let u2 = 3.0 * c - 4.0 * d + e;
    let eps = real(1e-6);
    let s0 = eps + 13.0 / 12.0 * t0 * t0 + 0.25 * u0 * u0;
    let s1 = eps + 13.0 / 12.0 * t1 * t1 + 0.25 * u1 * u1;
    let s2 = eps + 13.0 / 12.0 * t2 * t2 + 0.25 * u2 * u2;
    let w0 = 0.1 / (s0 * s0);
    let w1 = 0.6 / (s1 * s1);
    let w2 = 0.3 / (s2 * s2);
    return (w0 * q0 + w1 * q1 + w2 * q2) / (w0 + w1 + w2);
}

// The flux of component c along a through the point half-way between its
// face q (array index p) and the next along a (fluid-proc's advection.rs).
fn flux(c: u32, a: u32, p: u32, q: vec3<i32>) -> real {
    let sa = cstride(c)[a];
    var v: real;
    if a == c {
        v = 0.5 * (rd(p) + rd(p + sa));
    } else {
        var r = q + unit(a);
        let hi = at(a, r);
        r[c] -= 1;
        v = 0.5 * (rd(hi) + rd(at(a, r)));
    }
    var value: real;
    if v >= 0.0 {
        value = weno(rd(p - 2u * sa), rd(p - sa), rd(p), rd(p + sa), rd(p + 2u * sa));
    } else {
        value = weno(rd(p + 3u * sa), rd(p + 2u * sa), rd(p + sa), rd(p), rd(p - sa));
    }
    return v * value;
}

// Σ_a (x₊ − 2x + x₋)/h_a² at index p of component c's array.
fn laplacian(c: u32, p: u32) -> real {
    let st = cstride(c);
    var sum: real = 0.0;
    for (var a = 0u; a < 3u; a++) {
        if GH[a] > 0u {
            sum += s[INV_H2 + a] * (rd(p + st[a]) - 2.0 * rd(p) + rd(p - st[a]));
        }
    }
    return sum;
}

// On each unknown face of component op.comp: Nⁿ = ∇·(u u_c) into op.o0,
// and the right-hand side Δt(−N^{n+½} − ∇q + νLuⁿ) of its change into
// op.o2, N^{n−1} read from op.o1 (fluid-proc's component.rs).
@compute @workgroup_size(256)
fn rhs(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = thread(gid, groups);
    if t >= box_size() {
        return;
    }
    let c = op.comp;
    let pc = box_coords(t);
    let rel = box_index(pc);
    let q = vec3<i32>(pc) - vec3<i32>(GH);
    let p = U_OFF[c] + rel;
    var adv: real = 0.0;
    for (var a = 0u; a < 3u; a++) {
        if GH[a] > 0u {
            let sa = cstride(c)[a];
            adv += (flux(c, a, p, q) - flux(c, a, p - sa, q - unit(a))) * s[INV_H + a];
        }
    }
    wr(op.o0 + rel, adv);
    let advected = s[AB0] * adv + s[AB1] * rd(op.o1 + rel);
    let grad_q = face_gradient(Q_OFF, c, q);
    wr(op.o2 + rel, s[DT] * (-advected - grad_q + s[NU] * laplacian(c, p)));
}

// r = b − (I − αL)δ and p = r on the unknown faces: δ at o0, b at o1, r
// at o2, p at o3 (fluid-proc's `Helmholtz::first_residual`).
@compute @workgroup_size(256)
fn helm_residual(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = thread(gid, groups);
    if t >= box_size() || skipped() {
        return;
    }
    let rel = box_index(box_coords(t));
    let d = op.o0 + rel;
    let r = rd(op.o1 + rel) - (rd(d) - s[ALPHA] * laplacian(op.comp, d));
    wr(op.o2 + rel, r);
    wr(op.o3 + rel, r);
}

// q = (I − αL)p on the unknown faces: p at o0, q at o1.
@compute @workgroup_size(256)
fn helm_apply(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = thread(gid, groups);
    if t >= box_size() || skipped() {
        return;
    }
    let rel = box_index(box_coords(t));
    let p = op.o0 + rel;
    wr(op.o1 + rel, rd(p) - s[ALPHA] * laplacian(op.comp, p));
}

// ---- Vector operations and sums ------------------------------------------

// out (o0) = y (o1; none where kind has bit 1) + c·z (o2), c = s[slot],
// negated where kind has bit 0; over the op's box.
@compute @workgroup_size(256)
fn lin(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = thread(gid, groups);
    if t >= box_size() || skipped() {
        return;
    }
    let rel = box_index(box_coords(t));
    let c = select(s[op.slot], -s[op.slot], (op.kind & 1u) == 1u);
    var y: real = 0.0;
    if (op.kind & 2u) == 0u {
        y = rd(op.o1 + rel);
    }
    wr(op.o0 + rel, y + c * rd(op.o2 + rel));
}

// x (o0) −= s[slot] over the op's box.
@compute @workgroup_size(256)
fn shift(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = thread(gid, groups);
    if t >= box_size() || skipped() {
        return;
    }
    let rel = box_index(box_coords(t));
    wr(op.o0 + rel, rd(op.o0 + rel) - (s[op.slot]));
}

// Whether the whole workgroup skips this pass (a uniform value, so that
// the barriers below stay in uniform control flow).
fn workgroup_skips(local: u32) -> bool {
    if local == 0u {
        shared_flag = select(0u, 1u, skipped());
    }
    return workgroupUniformLoad(&shared_flag) == 1u;
}

// The workgroup's sum (kind 0: x·y, 1: x) or largest |x| (kind 2) over the
// op's box, x at o0 and y at o1, into part[workgroup].
@compute @workgroup_size(256)
fn reduce(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
    @builtin(workgroup_id) wid: vec3<u32>,
) {
    if workgroup_skips(local) {
        return;
    }
    let t = thread(gid, groups);
    var v: real = 0.0;
    if t < box_size() {
        let rel = box_index(box_coords(t));
        let x = rd(op.o0 + rel);
        if op.kind == 0u {
            v = x * rd(op.o1 + rel);
        } else if op.kind == 1u {
            v = x;
        } else {
            v = abs(x);
        }
    }
    shared_sum[local] = v;
    combine_shared(local, op.kind == 2u);
    if local == 0u {
        part[wid.x + wid.y * groups.x] = shared_sum[0];
    }
}

// shared_sum[0] ← the sum (or the largest) of shared_sum.
fn combine_shared(local: u32, largest: bool) {
    for (var half = WG / 2u; half > 0u; half /= 2u) {
        workgroupBarrier();
        if local < half {
            let a = shared_sum[local];
            let b = shared_sum[local + half];
            shared_sum[local] = select(a + b, max(a, b), largest);
        }
    }
    workgroupBarrier();
}

// s[slot] ← the sum (kind 0), the largest (1) or the mean over `aux`
// entries (2) of the op.count partial sums.
@compute @workgroup_size(256)
fn finish(@builtin(local_invocation_index) local: u32) {
    if workgroup_skips(local) {
        return;
    }
    let largest = op.kind == 1u;
    var v: real = 0.0;
    for (var i = local; i < op.count; i += WG) {
        v = select(v + part[i], max(v, part[i]), largest);
    }
    shared_sum[local] = v;
    combine_shared(local, largest);
    if local == 0u {
        var total = shared_sum[0];
        if op.kind == 2u {
            total = total / real(op.aux);
        }
        s[op.slot] = total;
    }
}

// The solves' scalar arithmetic, on one thread: op.kind names the step.
@compute @workgroup_size(1)
fn scalar() {
    if skipped() {
        return;
    }
    let b = op.solve;
    switch op.kind {
        // Viscous start: stop at once where b = 0 (δ = 0) or r is small.
        case 0u: {
            let norm_b = sqrt(s[b + BB]);
            if norm_b == 0.0 {
                s[b + DONE] = 2.0;
                return;
            }
            s[b + GOAL] = s[TOL_V] * norm_b;
            s[b + SCALE] = norm_b;
            if sqrt(s[b + RR]) <= s[b + GOAL] {
                s[b + DONE] = 1.0;
            }
        }
        // The step along p: rr/pq (viscous, kind 1) or rz/pq (pressure, 2).
        case 1u, 2u: {
            let step = select(s[b + RZ], s[b + RR], op.kind == 1u) / s[b + PQ];
            if !is_finite(step) {
                s[b + FAIL] = 1.0;
                s[b + DONE] = 1.0;
                return;
            }
            s[b + STEP] = step;
        }
        // Viscous next: stop, or β = rr_new/rr.
        case 3u: {
            s[b + ITER] += 1.0;
            if sqrt(s[b + RRN]) <= s[b + GOAL] {
                s[b + DONE] = 1.0;
                return;
            }
            s[b + BETA] = s[b + RRN] / s[b + RR];
            s[b + RR] = s[b + RRN];
        }
        // Pressure start: ‖b‖ of b's mean-free part where A is singular;
        // stop relative to the larger of it and the first residual.
        case 4u: {
            var mean: real = 0.0;
            if SINGULAR {
                mean = s[b + MEANB];
            }
            let norm_b = sqrt(max(s[b + BB] - s[CELLS] * mean * mean, 0.0));
            let res = sqrt(s[b + RR]);
            let scale = max(norm_b, res);
            s[b + SCALE] = scale;
            s[b + GOAL] = s[TOL_P] * scale;
            if res <= s[b + GOAL] || scale == 0.0 {
                s[b + DONE] = 1.0;
            }
        }
        // Pressure residual: stop once small.
        case 5u: {
            s[b + ITER] += 1.0;
            s[b + RR] = s[b + RRN];
            if sqrt(s[b + RRN]) <= s[b + GOAL] {
                s[b + DONE] = 1.0;
            }
        }
        // Pressure next: β = rz_new/rz.
        default: {
            s[b + BETA] = s[b + RZN] / s[b + RZ];
            s[b + RZ] = s[b + RZN];
        }
    }
}

// ---- The projection --------------------------------------------------------

// o0 ← −∇·u/Δt per cell (fluid-proc's faces::divergence).
@compute @workgroup_size(256)
fn divergence(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = thread(gid, groups);
    if t >= op.count {
        return;
    }
    let c = vec3<i32>(cell_coords(NC, t));
    var div: real = 0.0;
    for (var d = 0u; d < 3u; d++) {
        if NC[d] > 1u {
            div += (rd(at(d, c + unit(d))) - rd(at(d, c))) * s[INV_H + d];
        }
    }
    wr(op.o0 + t, div * (-1.0 / s[DT]));
}

// (A x)_c = −∇²ₕx at cell t of level l, x at `off` (fluid-proc's
// laplacian.rs): a side of given velocity drops its term, an outflow
// (φ = 0 on the face) doubles it, a periodic side wraps.
fn poisson(l: u32, off: u32, t: u32) -> real {
    let n = LEVEL_N[l];
    let c = cell_coords(n, t);
    var diag: real = 0.0;
    var sum: real = 0.0;
    for (var d = 0u; d < 3u; d++) {
        if n[d] == 1u {
            continue;
        }
        let w = s[LEVEL_H2 + 3u * l + d];
        for (var up = 0u; up < 2u; up++) {
            let at_side = select(c[d] == 0u, c[d] + 1u == n[d], up == 1u);
            var m = c;
            if !at_side {
                m[d] = select(c[d] - 1u, c[d] + 1u, up == 1u);
            } else {
                let side = SIDE[2u * d + up];
                if side == OUTFLOW {
                    diag += 2.0 * w;
                    continue;
                }
                if side != PERIODIC {
                    continue;
                }
                m[d] = select(n[d] - 1u, 0u, up == 1u);
            }
            diag += w;
            sum += w * rd(off + cell_index(n, m));
        }
    }
    return diag * rd(off + t) - sum;
}

// A's diagonal at cell t of level l.
fn poisson_diagonal(l: u32, t: u32) -> real {
    let n = LEVEL_N[l];
    let c = cell_coords(n, t);
    var diag: real = 0.0;
    for (var d = 0u; d < 3u; d++) {
        if n[d] == 1u {
            continue;
        }
        let w = s[LEVEL_H2 + 3u * l + d];
        for (var up = 0u; up < 2u; up++) {
            let at_side = select(c[d] == 0u, c[d] + 1u == n[d], up == 1u);
            let side = SIDE[2u * d + up];
            if !at_side || side == PERIODIC {
                diag += w;
            } else if side == OUTFLOW {
                diag += 2.0 * w;
            }
        }
    }
    return diag;
}

// On level op.comp: o1 ← A x (kind 0) or b − A x (kind 1), x at o0, b at o2.
@compute @workgroup_size(256)
fn poisson_apply(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = thread(gid, groups);
    if t >= op.count || skipped() {
        return;
    }
    let ax = poisson(op.comp, op.o0, t);
    if op.kind == 1u {
        wr(op.o1 + t, rd(op.o2 + t) - ax);
    } else {
        wr(op.o1 + t, ax);
    }
}

// One Gauss–Seidel update of cell t of level l for A x = b (x at xo, b at
// bo) where it has colour `colour` ((i + j + k) mod 2).
fn relax(l: u32, bo: u32, xo: u32, t: u32, colour: u32) {
    let c = cell_coords(LEVEL_N[l], t);
    if (c.x + c.y + c.z) % 2u != colour {
        return;
    }
    let d = poisson_diagonal(l, t);
    if d != 0.0 {
        // A x = d·x − Σ: x ← (b + Σ)/d = x + (b − A x)/d.
        wr(xo + t, rd(xo + t) + ((rd(bo + t) - poisson(l, xo, t)) / d));
    }
}

// One colour's sweep (op.aux) of level op.comp: b at o0, x at o1.
@compute @workgroup_size(256)
fn sweep(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = thread(gid, groups);
    if t >= op.count || skipped() {
        return;
    }
    relax(op.comp, op.o0, op.o1, t, op.aux);
}

// Whether level l halves along d into level l + 1.
fn halves(l: u32, d: u32) -> bool {
    return LEVEL_N[l + 1u][d] < LEVEL_N[l][d];
}

// Level op.comp's residual (o0) restricted to level op.comp + 1's b (o1):
// each coarse cell the mean of its children, in ascending order.
@compute @workgroup_size(256)
fn restriction(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = thread(gid, groups);
    if t >= op.count || skipped() {
        return;
    }
    let l = op.comp;
    let fine = LEVEL_N[l];
    let p = cell_coords(LEVEL_N[l + 1u], t);
    var kids = vec3<u32>(1u, 1u, 1u);
    var first = p;
    var share: real = 1.0;
    for (var d = 0u; d < 3u; d++) {
        if halves(l, d) {
            kids[d] = 2u;
            first[d] = 2u * p[d];
            share *= 0.5;
        }
    }
    var sum: real = 0.0;
    for (var k = 0u; k < kids.z; k++) {
        for (var j = 0u; j < kids.y; j++) {
            for (var i = 0u; i < kids.x; i++) {
                sum += rd(op.o0 + cell_index(fine, first + vec3<u32>(i, j, k))) * share;
            }
        }
    }
    wr(op.o1 + t, sum);
}

// Level op.comp's x (o0) += its parents' correction on level op.comp + 1 (o1).
@compute @workgroup_size(256)
fn prolongation(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = thread(gid, groups);
    if t >= op.count || skipped() {
        return;
    }
    let l = op.comp;
    var c = cell_coords(LEVEL_N[l], t);
    for (var d = 0u; d < 3u; d++) {
        if halves(l, d) {
            c[d] /= 2u;
        }
    }
    wr(op.o0 + t, rd(op.o0 + t) + (rd(op.o1 + cell_index(LEVEL_N[l + 1u], c))));
}

// The coarsest level op.comp (b at o0, x at o1) on one workgroup: x from
// zero by COARSEST_SWEEPS symmetric red–black sweeps, mean-free where A is
// singular (fluid-proc's multigrid.rs).
@compute @workgroup_size(256)
fn coarsest(@builtin(local_invocation_index) local: u32) {
    let l = op.comp;
    let n = op.count;
    for (var t = local; t < n; t += WG) {
        wr(op.o1 + t, 0.0);
    }
    storageBarrier();
    for (var sweep = 0u; sweep < 4u * COARSEST_SWEEPS; sweep++) {
        // Red, black, black, red.
        let k = sweep % 4u;
        let colour = select(1u, 0u, k == 0u || k == 3u);
        for (var t = local; t < n; t += WG) {
            relax(l, op.o0, op.o1, t, colour);
        }
        storageBarrier();
        workgroupBarrier();
    }
    if !SINGULAR {
        return;
    }
    var v: real = 0.0;
    for (var t = local; t < n; t += WG) {
        v += rd(op.o1 + t);
    }
    shared_sum[local] = v;
    combine_shared(local, false);
    let mean = shared_sum[0] / real(n);
    for (var t = local; t < n; t += WG) {
        wr(op.o1 + t, rd(op.o1 + t) - (mean));
    }
}

// u_d −= Δt ∂φ/∂x_d on every face of component op.comp (the op's box).
@compute @workgroup_size(256)
fn gradient(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = thread(gid, groups);
    if t >= box_size() {
        return;
    }
    let pc = box_coords(t);
    let q = vec3<i32>(pc) - vec3<i32>(GH);
    let d = op.comp;
    wr(U_OFF[d] + box_index(pc), rd(U_OFF[d] + box_index(pc)) - (s[DT] * face_gradient(PHI_OFF, d, q)));
}

// Eq. (3.20) with A = −∇²: q ← q + φ + (νΔt/2)Aφ per cell.
@compute @workgroup_size(256)
fn pressure_update(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = thread(gid, groups);
    if t >= op.count {
        return;
    }
    wr(Q_OFF + t, rd(Q_OFF + t) + (rd(PHI_OFF + t) + s[ALPHA] * poisson(0u, PHI_OFF, t)));
}

// o0 ← Σ_a |u_a|/h_a per cell, u_a the mean of the cell's two a-faces: the
// Courant number of a unit step (fluid-proc's `Incompressible::courant`).
@compute @workgroup_size(256)
fn courant(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = thread(gid, groups);
    if t >= op.count {
        return;
    }
    let c = vec3<i32>(cell_coords(NC, t));
    var sum: real = 0.0;
    for (var a = 0u; a < 3u; a++) {
        if NC[a] > 1u {
            sum += abs(0.5 * (rd(at(a, c)) + rd(at(a, c + unit(a))))) * s[INV_H + a];
        }
    }
    wr(op.o0 + t, sum);
}

// ---- Bodies and the canopy in the flow ---------------------------------
//
// Direct forcing with Peskin's δ (fluid-proc's immersed.rs): every marker
// reads the air at its place, its push follows, and the pushes are spread
// back. Spreading sums into faces that several markers reach: the markers
// are sorted into blocks of 4 cells a side, one thread spreads a block's
// markers in their order, and a dispatch takes blocks of one colour only,
// two blocks apart along some axis, whose kernels (±2 cells) never meet.
// So no two threads write one face, and the sums come out the same every
// run: no atomics (WGSL has none for reals).

// A marker's fields (`markers.rs`).
const MK_X: u32 = 0u;
const MK_NORMAL: u32 = 3u;
const MK_AREA: u32 = 6u;
const MK_TARGET: u32 = 7u;
const MK_LAW: u32 = 10u;
const MK_KIND: u32 = 12u;
const MK_AIR: u32 = 13u;
const MK_PUSH: u32 = 16u;
const MK_ACC: u32 = 19u;
// Kinds: a body, a closed sheet, a porous sheet.
const SHEET: real = 1.0;
const POROUS: real = 2.0;

// Peskin's 4-point φ (fluid-proc's delta.rs, Peskin 2002 eq. 6.27).
fn phi(r0: real) -> real {
    let r = abs(r0);
    if r <= 1.0 {
        return (3.0 - 2.0 * r + sqrt(1.0 + 4.0 * r - 4.0 * r * r)) / 8.0;
    }
    if r <= 2.0 {
        return (5.0 - 2.0 * r - sqrt(max(-7.0 + 12.0 * r - 4.0 * r * r, 0.0))) / 8.0;
    }
    return 0.0;
}

// The places of component c's faces a point's kernel reaches along each
// axis and their weights (fluid-proc's `Reach`): wrapped round a periodic
// axis; outside the box, or a side face, no weight.
struct Reach {
    index: array<vec4<i32>, 3>,
    weight: array<vec4<real>, 3>,
}

fn reach(c: u32, x: vec3<real>) -> Reach {
    var out: Reach;
    for (var d = 0u; d < 3u; d++) {
        let n = i32(NC[d]);
        let shift = select(real(0.5), real(0.0), d == c);
        let r = x[d] * s[INV_H + d] - shift;
        let first = i32(floor(r)) - 1;
        let periodic = SIDE[2u * d] == PERIODIC;
        // A side face (0 or n along c) is no unknown; cells 0..n − 1.
        let lo = select(0, 1, d == c);
        let hi = n - 1;
        for (var j = 0; j < 4; j++) {
            let i = first + j;
            let w = phi(r - real(i));
            if periodic {
                out.index[d][j] = ((i % n) + n) % n;
                out.weight[d][j] = w;
            } else if i >= lo && i <= hi {
                out.index[d][j] = i;
                out.weight[d][j] = w;
            } else {
                out.index[d][j] = 0;
                out.weight[d][j] = 0.0;
            }
        }
    }
    return out;
}

fn marker_x(k: u32) -> vec3<real> {
    let o = k * MARKER + MK_X;
    return vec3<real>(mk[o], mk[o + 1u], mk[o + 2u]);
}

// Whether marker k takes part in forcing pass `pass` (0: the porous
// sheets' drag, else the others' forcing).
fn in_pass(k: u32, forcing: u32) -> bool {
    return (mk[k * MARKER + MK_KIND] == POROUS) == (forcing == 0u);
}

// The air at each marker of the pass op.aux, into its MK_AIR.
@compute @workgroup_size(256)
fn interpolate(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let k = thread(gid, groups);
    if k >= op.count || !in_pass(k, op.aux) {
        return;
    }
    let x = marker_x(k);
    for (var c = 0u; c < 3u; c++) {
        var v: real = 0.0;
        if NC[c] > 1u {
            let r = reach(c, x);
            for (var kk = 0; kk < 4; kk++) {
                let wk = r.weight[2][kk];
                if wk == 0.0 {
                    continue;
                }
                for (var j = 0; j < 4; j++) {
                    let wj = wk * r.weight[1][j];
                    if wj == 0.0 {
                        continue;
                    }
                    for (var i = 0; i < 4; i++) {
                        let w = wj * r.weight[0][i];
                        if w != 0.0 {
                            let q = vec3<i32>(r.index[0][i], r.index[1][j], r.index[2][kk]);
                            v += w * rd(at(c, q));
                        }
                    }
                }
            }
        }
        // Over the ground, as the markers' targets are.
        mk[k * MARKER + MK_AIR + c] = v + s[FRAME + c];
    }
}

// Each marker's push of the pass op.aux (momentum per unit density
// F_k ΔV_k Δt, fluid-proc's `porous_pushes` and `solid_pushes`), into its
// MK_PUSH, and added to what it has given the fluid (MK_ACC).
@compute @workgroup_size(256)
fn pushes(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let k = thread(gid, groups);
    if k >= op.count || !in_pass(k, op.aux) {
        return;
    }
    let o = k * MARKER;
    let n = vec3<real>(mk[o + MK_NORMAL], mk[o + MK_NORMAL + 1u], mk[o + MK_NORMAL + 2u]);
    let air = vec3<real>(mk[o + MK_AIR], mk[o + MK_AIR + 1u], mk[o + MK_AIR + 2u]);
    let v = vec3<real>(mk[o + MK_TARGET], mk[o + MK_TARGET + 1u], mk[o + MK_TARGET + 2u]);
    let area = mk[o + MK_AREA];
    var push: vec3<real>;
    if op.aux == 0u {
        // The fabric's Ergun drag on the air crossing it, implicit in the
        // crossing speed: κ = Δt·(3/8)/(ρh).
        let a = mk[o + MK_LAW];
        let b = mk[o + MK_LAW + 1u];
        let kappa = s[DT] * 0.375 / (s[RHO] * s[SPACING]);
        let seen = dot(air - v, n);
        let linear = 1.0 + kappa * a;
        let root = sqrt(linear * linear + 4.0 * kappa * b * abs(seen));
        let w = 2.0 * seen / (linear + root);
        let drop = a * w + b * w * abs(w);
        push = n * (-s[DT] * drop * area / s[RHO]);
    } else {
        var e = v - air;
        if mk[o + MK_KIND] == SHEET {
            e = n * dot(e, n);
        }
        push = e * (area * s[SPACING]);
    }
    for (var c = 0u; c < 3u; c++) {
        let p = select(0.0, push[c], NC[c] > 1u);
        mk[o + MK_PUSH + c] = p;
        mk[o + MK_ACC + c] += p;
    }
}

// The pushes of pass op.aux spread to the faces, one block of markers a
// thread, the blocks of one colour (op.o0: where its pairs start).
@compute @workgroup_size(64)
fn spread(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = gid.x + gid.y * groups.x * 64u;
    if t >= op.count {
        return;
    }
    let first = blocks[op.o0 + 2u * t];
    let end = blocks[op.o0 + 2u * t + 1u];
    for (var k = first; k < end; k++) {
        if !in_pass(k, op.aux) {
            continue;
        }
        let x = marker_x(k);
        for (var c = 0u; c < 3u; c++) {
            let push = mk[k * MARKER + MK_PUSH + c];
            if NC[c] == 1u || push == 0.0 {
                continue;
            }
            let r = reach(c, x);
            for (var kk = 0; kk < 4; kk++) {
                for (var j = 0; j < 4; j++) {
                    let wj = r.weight[2][kk] * r.weight[1][j];
                    for (var i = 0; i < 4; i++) {
                        let w = wj * r.weight[0][i];
                        if w != 0.0 {
                            let q = vec3<i32>(r.index[0][i], r.index[1][j], r.index[2][kk]);
                            wr(at(c, q), rd(at(c, q)) + (push * w / s[CELL]));
                        }
                    }
                }
            }
        }
    }
}
