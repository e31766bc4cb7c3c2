// The structure's explicit step on the device (dissertation chapter 5): the
// same three passes as the CPU path (structure-proc's forces/assembly.rs),
// so that one network gives the same numbers on both to round-off:
//
// - `element_slots`: every spring, membrane edge and damper writes its force
//   on its first node into a slot of its own (its second node gets the
//   opposite), every pressure triangle its load on each vertex;
// - `gather`: every node sums m·g and its slots, in the CPU's order;
// - `combine`: out ← a + c·b, or a + c·b/m where `scaled`: the kicks and
//   drifts every scheme is made of (structure-proc's integrators/mod.rs).
//
// The host prepends `alias real = f64;` (or f32 where the adapter lacks
// f64) and the constants NODES, SPRINGS, MEMBRANE (triangles), DAMPERS,
// TRIANGLES (pushed by a pressure jump), DAMPING_LAW, POROUS and REACTION
// (the vector that sums the impulse on nodes with 1/m = 0). Every
// vector (positions, velocities, forces, stage values) lives in `vecs`, 3
// reals a node, vector k at offset 3·NODES·k; each dispatch names its
// vectors in `op` (a dynamic offset into one uniform buffer per step).
// Slots: one per spring, three per membrane triangle, one per damper, one
// per pressure triangle, in that order.

struct Op {
    out: u32,
    a: u32,
    b: u32,
    // coefficient index << 2 | reacts << 1 | scaled by 1/m
    coef: u32,
}

@group(0) @binding(0) var<storage, read_write> vecs: array<real>;
@group(0) @binding(1) var<storage, read_write> slots: array<real>;
// The elements' nodes: springs 2, membrane triangles 3, dampers 2, pressure
// triangles 3 each, family after family.
@group(0) @binding(2) var<storage, read> element_nodes: array<u32>;
// Springs: k, rest length, compressive tolerance, 1 for a string; membrane
// triangles: 3 rest lengths, Q by rows; dampers: c, slack length.
@group(0) @binding(3) var<storage, read> elements: array<real>;
// Mass then 1/m per node.
@group(0) @binding(4) var<storage, read> nodes: array<real>;
// start[0..=NODES], then slot << 1 | subtracted.
@group(0) @binding(5) var<storage, read> assembly: array<u32>;
// Gravity (3); the porous law: free stream (3), A, B, porosity, thickness;
// from COEFS on, the step's coefficients.
@group(0) @binding(6) var<storage, read> params: array<real>;
@group(0) @binding(7) var<uniform> op: Op;
// The fluid's pressure jump per pressure triangle [Pa].
@group(0) @binding(8) var<storage, read> received: array<real>;

const COEFS: u32 = 10u;
const WORKGROUP: u32 = 64u;
// Dispatches past 65 535 workgroups spread over y.
fn index(gid: vec3<u32>, groups: vec3<u32>) -> u32 {
    return gid.x + gid.y * groups.x * WORKGROUP;
}

fn point(vector: u32, n: u32) -> vec3<real> {
    let o = 3u * (NODES * vector + n);
    return vec3<real>(vecs[o], vecs[o + 1u], vecs[o + 2u]);
}

// Hookean spring (thesis eq. 67) or string, tension only beyond its
// compressive tolerance (thesis eq. 3): k δ e on the first node.
fn spring(s: u32, x: u32) -> vec3<real> {
    let d = point(x, element_nodes[2u * s + 1u]) - point(x, element_nodes[2u * s]);
    let l = sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    let k = elements[4u * s];
    let rest = elements[4u * s + 1u];
    var stretch = l - rest;
    if elements[4u * s + 3u] != 0.0 {
        stretch = max(l - rest - elements[4u * s + 2u], 0.0);
    }
    var per_length: real = 0.0;
    if l > 0.0 {
        per_length = k * stretch / l;
    }
    return d * per_length;
}

// Viscous damper along a spring: thesis eq. (68) (DAMPING_LAW 0, the whole
// relative velocity) or dissertation eq. (2.38) (1, along the spring); idle
// below its slack length.
fn damper(k: u32, x: u32, v: u32) -> vec3<real> {
    let at = 2u * SPRINGS + 3u * MEMBRANE + 2u * k;
    let d = point(x, element_nodes[at + 1u]) - point(x, element_nodes[at]);
    let l = sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    let r = 4u * SPRINGS + 12u * MEMBRANE + 2u * k;
    let c = elements[r];
    if !(l > elements[r + 1u] && l > 0.0) {
        return vec3<real>(0.0, 0.0, 0.0);
    }
    let dv = point(v, element_nodes[at + 1u]) - point(v, element_nodes[at]);
    if DAMPING_LAW == 0u {
        return dv * c;
    }
    let e = d / l;
    return e * (c * (e.x * dv.x + e.y * dv.y + e.z * dv.z));
}

fn store(slot: u32, f: vec3<real>) {
    slots[3u * slot] = f.x;
    slots[3u * slot + 1u] = f.y;
    slots[3u * slot + 2u] = f.z;
}

// Delingette's triangular springs (dissertation eqs. 2.29–2.36): each edge
// pulls its ends with the tension T = Q·dl, dl the edges' length changes;
// the slot of edge e holds the force on its first vertex.
fn membrane(m: u32, x: u32) {
    let at = 2u * SPRINGS + 3u * m;
    let p0 = point(x, element_nodes[at]);
    let p1 = point(x, element_nodes[at + 1u]);
    let p2 = point(x, element_nodes[at + 2u]);
    let d = array<vec3<real>, 3>(p1 - p0, p2 - p1, p0 - p2);
    let r = 4u * SPRINGS + 12u * m;
    var l: array<real, 3>;
    var dl: array<real, 3>;
    for (var e = 0u; e < 3u; e++) {
        l[e] = sqrt(d[e].x * d[e].x + d[e].y * d[e].y + d[e].z * d[e].z);
        dl[e] = l[e] - elements[r + e];
    }
    for (var e = 0u; e < 3u; e++) {
        let q = r + 3u + 3u * e;
        let t = elements[q] * dl[0] + elements[q + 1u] * dl[1] + elements[q + 2u] * dl[2];
        store(SPRINGS + 3u * m + e, d[e] * (t / l[e]));
    }
}

// The porous law's jump on a triangle (thesis eqs. 6, 9, 10): the air's
// velocity relative to the triangle's mean, along its normal, through the
// fabric; `n` is twice the area times the unit normal.
fn porous_jump(n: vec3<real>, t: u32, v: u32) -> real {
    let len = sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
    if len == 0.0 {
        return 0.0;
    }
    let normal = n / len;
    let at = 2u * SPRINGS + 3u * MEMBRANE + 2u * DAMPERS + 3u * t;
    let centre = (point(v, element_nodes[at]) + point(v, element_nodes[at + 1u]) + point(v, element_nodes[at + 2u])) / 3.0;
    let stream = vec3<real>(params[3], params[4], params[5]);
    var v_normal: real = 0.0;
    for (var c = 0u; c < 3u; c++) {
        v_normal += normal[c] * (stream[c] - centre[c]);
    }
    let forchheimer = params[8] * v_normal;
    return params[9] * (params[6] * forchheimer + params[7] * forchheimer * abs(forchheimer));
}

// A third of jump·area·n on each vertex of pressure triangle t: the fluid's
// jump plus the porous law's.
fn pressure(t: u32, x: u32, v: u32) -> vec3<real> {
    let at = 2u * SPRINGS + 3u * MEMBRANE + 2u * DAMPERS + 3u * t;
    let p0 = point(x, element_nodes[at]);
    let e1 = point(x, element_nodes[at + 1u]) - p0;
    let e2 = point(x, element_nodes[at + 2u]) - p0;
    let n = vec3<real>(e1.y * e2.z - e1.z * e2.y, e1.z * e2.x - e1.x * e2.z, e1.x * e2.y - e1.y * e2.x);
    var jump = received[t];
    if POROUS != 0u {
        jump = jump + porous_jump(n, t, v);
    }
    if jump == 0.0 {
        return vec3<real>(0.0, 0.0, 0.0);
    }
    return n * (jump / 6.0);
}

// One thread an element: springs, membrane triangles, dampers, pressure
// triangles.
@compute @workgroup_size(64)
fn element_slots(@builtin(global_invocation_id) gid: vec3<u32>,
                 @builtin(num_workgroups) groups: vec3<u32>) {
    var k = index(gid, groups);
    if k < SPRINGS {
        store(k, spring(k, op.a));
        return;
    }
    k -= SPRINGS;
    if k < MEMBRANE {
        membrane(k, op.a);
        return;
    }
    k -= MEMBRANE;
    if k < DAMPERS {
        store(SPRINGS + 3u * MEMBRANE + k, damper(k, op.a, op.b));
        return;
    }
    k -= DAMPERS;
    if k < TRIANGLES {
        store(SPRINGS + 3u * MEMBRANE + DAMPERS + k, pressure(k, op.a, op.b));
    }
}

@compute @workgroup_size(64)
fn gather(@builtin(global_invocation_id) gid: vec3<u32>,
          @builtin(num_workgroups) groups: vec3<u32>) {
    let n = index(gid, groups);
    if n >= NODES {
        return;
    }
    let m = nodes[2u * n];
    var sum = vec3<real>(params[0] * m, params[1] * m, params[2] * m);
    for (var e = assembly[n]; e < assembly[n + 1u]; e++) {
        let entry = assembly[NODES + 1u + e];
        let o = 3u * (entry >> 1u);
        let s = vec3<real>(slots[o], slots[o + 1u], slots[o + 2u]);
        if (entry & 1u) == 0u {
            sum += s;
        } else {
            sum -= s;
        }
    }
    let o = 3u * (NODES * op.out + n);
    vecs[o] = sum.x;
    vecs[o + 1u] = sum.y;
    vecs[o + 2u] = sum.z;
}

// Where 1/m = 0 (held and attached nodes) a kick leaves the velocity and
// sums its impulse into the REACTION vector, as the CPU's `kick` does.
@compute @workgroup_size(64)
fn combine(@builtin(global_invocation_id) gid: vec3<u32>,
           @builtin(num_workgroups) groups: vec3<u32>) {
    let i = index(gid, groups);
    if i >= 3u * NODES {
        return;
    }
    let c = params[COEFS + (op.coef >> 2u)];
    var step = c * vecs[3u * NODES * op.b + i];
    if (op.coef & 1u) != 0u {
        let w = nodes[2u * (i / 3u) + 1u];
        if (op.coef & 2u) != 0u && w == 0.0 {
            vecs[3u * NODES * REACTION + i] += step;
        }
        step = step * w;
    }
    vecs[3u * NODES * op.out + i] = vecs[3u * NODES * op.a + i] + step;
}
