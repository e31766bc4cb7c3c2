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
