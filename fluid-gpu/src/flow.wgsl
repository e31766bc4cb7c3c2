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

// Whether this pass is skipped: its solve is done (guard 1), its
// right-hand side was not zero (guard 2), or its solve is not done yet
// (guard 3: the step's end, submitted behind each batch of iterations).
fn skipped() -> bool {
    let done = s[op.solve + DONE];
    return (op.guard == 1u && done != 0.0) || (op.guard == 2u && done != 2.0)
        || (op.guard == 3u && done == 0.0);
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

