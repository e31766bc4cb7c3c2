// The predictor of the step (flow.wgsl's header holds the bindings and
// the layouts): WENO5 advection in flux form, the right-hand side of each
// component's change, and the Crank–Nicolson operator.

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

