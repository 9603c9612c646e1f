"""Depth of penetration: a run's penetration.csv read against its deck, and the theories a depth
is compared with (Bernoulli, the hydrodynamic limit, Alekseevskii-Tate, Lanz-Odermatt).

    import spall.penetration as pen
    r = pen.analyse("out/rod_into_rha_rz")          # a dict: V, L, D, depths, rate, status ...
    pen.lanz_odermatt(1500.0, 10.0, 17600.0, 7830.0, 300.0)   # P/L = 0.829

Every figure a run cannot give is None with the reason in r["notes"] (never NaN).
"""
import math

import numpy as np

from .run import Run

# Lanz & Odermatt (2000), "Post-perforation and penetration of long rods": their fit to
# Hohler & Stilp's tungsten-alloy rods into semi-infinite steel, rho in kg/m^3, V in km/s
# (the issue states the constants; the data scatter about +-5% around it).
LO = {"a": 0.921, "b0": 0.283, "b1": 0.0656, "c0": 138.0, "c1": -0.100}


def lanz_odermatt(V, L_over_D, rho_p, rho_t, BHN, c=LO):
    """P/L = a coth(b0 + b1 L/D) sqrt(rho_p/rho_t) exp(-(c0 + c1 BHN) BHN / (rho_p V^2)),
    V in m/s here (converted to the fit's km/s)."""
    v = V / 1000.0
    coth = 1.0 / math.tanh(c["b0"] + c["b1"] * L_over_D)
    s = (c["c0"] + c["c1"] * BHN) * BHN / (rho_p * v * v)
    return c["a"] * coth * math.sqrt(rho_p / rho_t) * math.exp(-s)


def bernoulli_rate(V, rho_p, rho_t):
    """U_B = V / (1 + sqrt(rho_t / rho_p)) (strengthless, steady; Austin 2013, Eq. 3.2)."""
    return V / (1.0 + math.sqrt(rho_t / rho_p))


def tate_rate(v, rho_p, rho_t, Yp, Rt):
    """The penetration rate u of 1/2 rho_p (v - u)^2 + Yp = 1/2 rho_t u^2 + Rt, 0 <= u <= v:
    0 where the target holds an eroding rod (Rt >= 1/2 rho_p v^2 + Yp), v where the rod no longer
    erodes (Yp >= 1/2 rho_t v^2 + Rt: a rigid rod)."""
    if 0.5 * rho_p * v * v + Yp <= Rt:
        return 0.0
    if Yp >= 0.5 * rho_t * v * v + Rt:
        return v
    a = 0.5 * (rho_p - rho_t)
    b = -rho_p * v
    c = 0.5 * rho_p * v * v + Yp - Rt
    if abs(a) < 1e-12 * rho_p:
        u = -c / b
    else:
        disc = max(b * b - 4.0 * a * c, 0.0)
        roots = [(-b - math.sqrt(disc)) / (2.0 * a), (-b + math.sqrt(disc)) / (2.0 * a)]
        ok = [r for r in roots if -1e-9 * v <= r <= v * (1.0 + 1e-9)]
        u = min(ok) if ok else 0.0
    return min(max(u, 0.0), v)


def tate(V, L, rho_p, rho_t, Yp, Rt, resolution=1e-3, max_steps=10**6):
    """Alekseevskii-Tate (Austin 2013, Eqs. 3.8-3.9): rho_p l dv/dt = -Yp, dl/dt = -(v - u),
    dP/dt = u, integrated (classical Runge-Kutta) until the rod is consumed or stops. Each step
    is `resolution` of the time the rod needs to be eroded or stopped at its present rates, so a
    slow end takes as many steps as a fast one. Returns {depth, U0, time, residual_length,
    residual_velocity, converged} (converged False if max_steps ran out first)."""
    def rhs(y):
        v, l, _ = y
        if l <= 0.0 or v <= 0.0:
            return np.zeros(3)
        u = tate_rate(v, rho_p, rho_t, Yp, Rt)
        # An eroding rod decelerates by Yp at its rear interface; a rigid one (u = v) by the
        # target's resistance on its nose.
        dv = -Yp / (rho_p * l) if u < v else -(Rt + 0.5 * rho_t * v * v) / (rho_p * l)
        return np.array([dv, -(v - u), u])

    y, t, converged = np.array([V, L, 0.0]), 0.0, False
    for _ in range(max_steps):
        if y[1] <= 1e-9 * L or y[0] <= 1e-9 * V or tate_rate(y[0], rho_p, rho_t, Yp, Rt) <= 0.0:
            converged = True
            break
        k1 = rhs(y)
        scales = [L / -k1[1] if k1[1] < 0.0 else math.inf, y[0] / -k1[0] if k1[0] < 0.0 else math.inf]
        dt = resolution * min(scales)
        k2 = rhs(y + 0.5 * dt * k1)
        k3 = rhs(y + 0.5 * dt * k2)
        k4 = rhs(y + dt * k3)
        y1 = y + dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
        if y1[1] < 0.0:
            # The rod is consumed within this step: end where its length reaches 0.
            f = y[1] / (y[1] - y1[1])
            y, t, converged = y + f * (y1 - y), t + f * dt, True
            break
        y, t = y1, t + dt
    return {"depth": float(y[2]), "U0": tate_rate(V, rho_p, rho_t, Yp, Rt), "time": t,
            "residual_length": float(max(y[1], 0.0)), "residual_velocity": float(max(y[0], 0.0)),
            "converged": converged}


def _young(material):
    """E from the shear modulus and the bulk modulus rho c0^2 (a Mie-Gruneisen or linear EOS)."""
    G = material.get("strength", {}).get("shear_modulus")
    eos = material.get("eos", {})
    c0 = eos.get("c0", eos.get("sound_speed"))
    K = eos.get("bulk_modulus", material["density"] * c0 * c0 if c0 else None)
    if G is None or K is None:
        return None
    return 9.0 * K * G / (3.0 * K + G)


def yield_of(material):
    """A material's quasi-static yield: von Mises Y, Johnson-Cook A, Zerilli-Armstrong's
    athermal yield; None for others."""
    s = material.get("strength", {})
    t = s.get("type")
    if t == "von_mises":
        return float(s["yield_stress"]), "von Mises yield_stress"
    if t == "johnson_cook":
        return float(s["A"]), "Johnson-Cook A"
    if t == "zerilli_armstrong" and "sigma_a" in s:
        return float(s["sigma_a"]), "Zerilli-Armstrong sigma_a"
    return None, f"no yield stress read from strength type '{t}'"


def tate_strengths(rod_material, target_material):
    """Y_p and R_t from the deck when not given: Y_p the rod's yield, R_t Tate's (1986) cavity
    estimate R_t = Y_t (2/3 + ln(0.57 E_t / Y_t)). Returns (Yp, Rt, how) or (None, None, why)."""
    Yp, how_p = yield_of(rod_material)
    Yt, how_t = yield_of(target_material)
    Et = _young(target_material)
    if Yp is None or Yt is None or Et is None:
        why = how_p if Yp is None else how_t if Yt is None else "no E for the target"
        return None, None, why
    Rt = Yt * (2.0 / 3.0 + math.log(0.57 * Et / Yt))
    how = (f"Y_p = {Yp / 1e6:.0f} MPa (the rod's {how_p}), R_t = {Rt / 1e6:.0f} MPa (Tate 1986: "
           f"Y_t (2/3 + ln(0.57 E_t/Y_t)), Y_t = {Yt / 1e6:.0f} MPa the target's {how_t}, "
           f"E_t = {Et / 1e9:.0f} GPa)")
    return Yp, Rt, how


def _interval_along(shape, n):
    """The span [lo, hi] of a shape's points projected on the unit direction n."""
    t = shape["type"]
    if t == "box":
        lo, hi = np.array(shape["min"], float), np.array(shape["max"], float)
        a, b = lo * n, hi * n
        return float(np.minimum(a, b).sum()), float(np.maximum(a, b).sum())
    if t == "sphere":
        c = float(np.array(shape["center"], float) @ n)
        return c - float(shape["radius"]), c + float(shape["radius"])
    if t in ("cylinder", "cone", "ogive"):
        axis = np.array(shape["axis"], float)
        axis /= np.linalg.norm(axis)
        base = float(np.array(shape["base"], float) @ n)
        top = base + float(shape["length"]) * float(axis @ n)
        # Across the axis a section reaches radius |n - (n.a) a| further either way.
        reach = float(shape["radius"]) * float(np.linalg.norm(n - (n @ axis) * axis))
        return min(base, top) - reach, max(base, top) + reach
    if t == "polygon":
        d = np.array(shape["points"], float) @ n
        return float(d.min()), float(d.max())
    if t == "union":
        spans = [_interval_along(part, n) for part in shape["shapes"]]
        return min(a for a, _ in spans), max(b for _, b in spans)
    if t == "difference":
        return _interval_along(shape["from"], n)
    raise ValueError(f"a penetrator of shape '{t}' has no length along the direction")


def _intervals_along(shape, n):
    """The spans a shape's parts cover along n, merged where they touch or overlap."""
    if shape["type"] != "union":
        return [_interval_along(shape, n)]
    spans = sorted(s for part in shape["shapes"] for s in _intervals_along(part, n))
    merged = []
    for lo, hi in spans:
        if merged and lo <= merged[-1][1]:
            merged[-1][1] = max(merged[-1][1], hi)
        else:
            merged.append([lo, hi])
    return [tuple(m) for m in merged]


def extent_along(shape, direction):
    """A shape's length along a unit direction: the length its points cover projected on it (a
    rod with a nose: shank and nose together; a union with gaps along the direction, such as a
    jet laid out as it flies by tools/jet_layout: its parts' lengths without the gaps, the
    length of the material)."""
    return sum(hi - lo for lo, hi in _intervals_along(shape, np.asarray(direction, float)))


def span_along(shape, direction):
    """The span of a shape's points projected on a unit direction, gaps included (a spaced
    target's rear face is this far behind its front)."""
    lo, hi = _interval_along(shape, np.asarray(direction, float))
    return hi - lo


def diameter_across(shape, direction, rz):
    """A rod's diameter across the direction: rz box 2 r_max (about the axis), plane box its
    width, cylinder, sphere, cone and ogive 2 radius, an rz polygon 2 r_max; a union or
    difference its first part's (the shank a nose is joined to)."""
    t = shape["type"]
    if t == "box":
        lo, hi = np.array(shape["min"], float), np.array(shape["max"], float)
        across = np.abs(hi - lo) * (1.0 - np.abs(direction))
        if rz:
            return 2.0 * float(max(abs(hi[0]), abs(lo[0])))
        return float(across.max())
    if t in ("cylinder", "sphere", "cone", "ogive"):
        return 2.0 * float(shape["radius"])
    if t == "polygon" and rz:
        return 2.0 * max(float(p[0]) for p in shape["points"])
    if t == "union":
        return diameter_across(shape["shapes"][0], direction, rz)
    if t == "difference":
        return diameter_across(shape["from"], direction, rz)
    return None


def _slope(t, depth, sel):
    return float(np.polyfit(t[sel], depth[sel], 1)[0]) if sel.sum() >= 3 else None


def arrest(t, depth, V, D):
    """The arrest: the first time after which the depth gains less than 1% of a rod diameter
    (an arrested rod may rebound: the depth then falls, which does not count as moving), if the
    last 5% of the run (three rows at least) move slower than 2% of V. None if the rod still
    penetrates at the run's end."""
    if len(t) < 3:
        return None
    tail = t >= t[-1] - 0.05 * (t[-1] - t[0])
    tail[-3:] = True  # at least the last three rows
    last = np.polyfit(t[tail], depth[tail], 1)[0]
    if last > 0.02 * V:
        return None
    ahead = np.maximum.accumulate(depth[::-1])[::-1]    # the deepest from each row on
    gain = ahead - depth
    k = int(np.argmax(gain <= 0.01 * D))
    return float(t[k])


def steady_window(t, depth, V, D, tol=0.10, start_diameters=2.0, t_end=None):
    """The steady window: from where the depth passes `start_diameters` rod diameters (past the
    impact's transient, Austin 2013 Sec. 5.2) to the latest time (before t_end, the arrest) at
    which the slopes of the window's first and last thirds agree within tol of the whole
    window's: a rate that falls (a decelerating rod) or jumps shows as thirds that differ. The depth of a
    particle method moves in steps of a particle layer, so rates over less than half a diameter
    are noise; the window must be a diameter deep at least. Returns (t0, t1, reason), t0 None
    with the reason when no such window exists."""
    start = np.nonzero(depth >= start_diameters * D)[0]
    if len(start) == 0:
        return None, None, (f"the rod never passed {start_diameters:g} diameters "
                            f"({depth.max() * 1e3:.2f} mm deep)")
    k0 = int(start[0])
    best = None
    for k1 in range(k0 + 6, len(t)):
        if t_end is not None and t[k1] > t_end:
            break
        if depth[k1] - depth[k0] < D:
            continue
        sel = (t >= t[k0]) & (t <= t[k1])
        third = (t[k1] - t[k0]) / 3.0
        s, s1, s2 = (_slope(t, depth, sel), _slope(t, depth, sel & (t <= t[k0] + third)),
                     _slope(t, depth, sel & (t >= t[k1] - third)))
        if None in (s, s1, s2) or s <= 0.0:
            continue
        if abs(s1 - s2) <= tol * s:
            best = k1
    if best is None:
        return None, None, (f"no window a diameter deep past {start_diameters:g} diameters "
                            f"({depth[k0] * 1e3:.2f} mm) whose first and last thirds' rates agree within "
                            f"{100 * tol:g}%: not steady")
    return float(t[k0]), float(t[best]), (f"detected: depth {depth[k0] * 1e3:.2f}-"
                                          f"{depth[best] * 1e3:.2f} mm ({(depth[best] - depth[k0]) / D:.1f} D), "
                                          f"its first and last thirds' rates within {100 * tol:g}%")


def _penetrator(deck, pen, n):
    """(V, L, D, rho_p, material dict, rows note) of the deck's penetrator."""
    bodies = {b["name"]: b for b in deck.get("body", [])}
    materials = {m["name"]: m for m in deck["material"]}
    jets = {j.get("name", f"jet{k + 1}"): j for k, j in enumerate(deck.get("jet", []))}
    rz = deck.get("run", {}).get("geometry") == "rz"
    first = pen["penetrator"][0]
    if first in jets:
        # A discrete jet: its leading segment's speed, its segments' total length, the widest
        # segment's diameter.
        jet = jets[first]
        rows = sorted(jet["segments"], key=lambda r: (r[4], r[0]))
        mat = materials[jet["material"]]
        return (float(rows[0][3]), sum(float(r[2]) for r in rows),
                2.0 * max(float(r[1]) for r in rows), float(mat["density"]), mat)
    rod = bodies[first]
    mat = materials[rod["material"]]
    rho_p = float(rod.get("initial_density", mat["density"]))
    V = float(np.array(rod.get("velocity", [0.0] * len(n)), float) @ n)
    L = sum(extent_along(bodies[b]["shape"], n) for b in pen["penetrator"] if b in bodies)
    L += sum(float(r[2]) for b in pen["penetrator"] if b in jets for r in jets[b]["segments"])
    return V, L, diameter_across(rod["shape"], np.abs(n), rz), rho_p, mat


def analyse(outdir, window=None, yp=None, rt=None, tate_from_deck=False, bhn=None, tol=0.10):
    """A run's penetration against the theories. window: (t0, t1) seconds, else detected. yp, rt:
    Tate's strengths (Pa); tate_from_deck: take them from the deck (tate_strengths). bhn: the
    target's Brinell hardness for Lanz-Odermatt. V is the penetrator's speed relative to the
    target's along the direction (a reverse-ballistic deck moves the target)."""
    run = Run(outdir)
    notes = []
    out = {"run": str(run.dir), "status": None, "notes": notes}
    summary = run.summary
    out["status"] = summary.get("status", "unknown") if summary else "unfinished"
    if summary and summary.get("status") == "failed":
        notes.append(f"the run failed: {summary.get('failure', '')[:200]}")
    out["wall_seconds"] = summary.get("wall_seconds") if summary else None
    deck = run.deck
    pen = deck.get("penetration")
    if pen is None:
        raise ValueError(f"{run.dir}/deck.toml has no [penetration] table")
    n = np.array(pen["direction"], float)
    n /= np.linalg.norm(n)
    V, L, D, rho_p, rod_mat = _penetrator(deck, pen, n)
    bodies = {b["name"]: b for b in deck.get("body", [])}
    materials = {m["name"]: m for m in deck["material"]}
    target = bodies[pen["target"]]
    V -= float(np.array(target.get("velocity", [0.0] * len(n)), float) @ n)
    tmat = materials[target["material"]]
    rho_t = float(target.get("initial_density", tmat["density"]))
    thickness = span_along(target["shape"], n)
    out.update({"V": V, "L": L, "D": D, "L_over_D": L / D if D else None, "rho_p": rho_p,
                "rho_t": rho_t, "target_thickness": thickness,
                "resolution": deck.get("run", {}).get("resolution", 1.0)})
    moving = V > 0.0
    if not moving:
        notes.append(f"the penetrator does not move toward the target (V = {V:g} m/s along the "
                     f"direction): no rates, Tate or Lanz-Odermatt")
    out.update({"U_bernoulli": bernoulli_rate(V, rho_p, rho_t) if moving else None,
                "hydrodynamic_depth": L * math.sqrt(rho_p / rho_t)})
    _theories(out, rod_mat, tmat, yp, rt, tate_from_deck, bhn, moving)
    d = run.penetration
    if d is None or len(d) == 0:
        notes.append("no penetration.csv rows")
        return _fill(out)
    _measure(out, d, thickness, window, tol, moving)
    return _fill(out)


def _theories(out, rod_mat, tmat, yp, rt, tate_from_deck, bhn, moving):
    """Tate's depth and Lanz-Odermatt's P/L for the run's rod and target."""
    V, L, D, rho_p, rho_t = out["V"], out["L"], out["D"], out["rho_p"], out["rho_t"]
    if yp is not None or rt is not None:
        Yp, Rt = yp or 0.0, rt or 0.0
        how = f"Y_p = {Yp / 1e6:g} MPa, R_t = {Rt / 1e6:g} MPa (given)"
    elif tate_from_deck:
        Yp, Rt, how = tate_strengths(rod_mat, tmat)
    else:
        Yp, Rt, how = None, None, "not computed: give --yp and --rt, or --tate-from-deck"
    out["tate_strengths"] = how
    out["tate_asked"] = yp is not None or rt is not None or tate_from_deck
    if Yp is not None and moving:
        T = tate(V, L, rho_p, rho_t, Yp, Rt)
        out.update({"tate_depth": T["depth"], "U_tate": T["U0"], "Yp": Yp, "Rt": Rt})
        if not T["converged"]:
            out["notes"].append("Tate: the integration ran out of steps before the rod stopped")
    if bhn is not None and D and moving:
        out["P_over_L_lanz_odermatt"] = lanz_odermatt(V, L / D, rho_p, rho_t, bhn)


def _measure(out, d, thickness, window, tol, moving):
    """The run's own figures from penetration.csv: deepest depth, arrest, residual velocity,
    the steady rate."""
    notes, V, L = out["notes"], out["V"], out["L"]
    D = out["D"] or L / 10.0
    t, depth = d["time"].astype(float), d["depth"].astype(float)
    tip = d["tip_velocity"].astype(float)
    out["series"] = {"time": t, "depth": depth, "rate": d["rate"].astype(float), "tip": tip}
    k = int(np.argmax(depth))
    out.update({"final_time": float(t[-1]), "final_depth": float(depth[-1]),
                "max_depth": float(depth[k]), "max_depth_time": float(t[k])})
    perforated = depth[k] >= thickness
    out["perforated"] = bool(perforated)
    if depth[k] <= 0.0:
        notes.append("the penetrator never entered the target")
    elif perforated:
        notes.append(f"perforated the {thickness * 1e3:.1f} mm target: no P/L (the depth "
                     f"includes the flight beyond its rear face)")
    else:
        out["P_over_L"] = float(depth[k]) / L
    if not moving:
        return
    ta = arrest(t, depth, V, D)
    out["arrest_time"] = ta
    if perforated:
        out["residual_velocity"] = float(tip[-1])
    elif ta is not None:
        out["residual_velocity"] = 0.0
    else:
        notes.append(f"still penetrating at {t[-1] * 1e6:.1f} us (tip at "
                     f"{tip[-1]:.0f} m/s): max depth, arrest and residual velocity not final")
    # The window ends before the arrest, and a diameter before the rear face of a perforated
    # target (the rear face's release speeds the rod up; past it the rod flies free).
    t_end = ta
    if perforated:
        t_exit = float(t[np.argmax(depth >= thickness - D)])
        t_end = t_exit if t_end is None else min(t_end, t_exit)
    if window:
        t0, t1 = window
        why = f"given: {t0 * 1e6:g}-{t1 * 1e6:g} us"
    else:
        t0, t1, why = steady_window(t, depth, V, D, tol, t_end=t_end)
    out["window_reason"] = why
    if t0 is None:
        notes.append(f"no steady rate: {why}")
        return
    sel = (t >= t0) & (t <= t1)
    if sel.sum() >= 3:
        out["U"] = float(np.polyfit(t[sel], depth[sel], 1)[0])
        out["window"] = [float(t[sel][0]), float(t[sel][-1])]
    else:
        notes.append(f"no steady rate: {sel.sum()} rows in the window ({why})")


KEYS = ("V", "L", "D", "U", "window", "max_depth", "final_depth", "arrest_time",
        "residual_velocity", "tate_depth", "U_tate", "P_over_L", "P_over_L_lanz_odermatt")


def _fill(out):
    for k in KEYS:
        out.setdefault(k, None)
    V, U, UB = out["V"], out["U"], out.get("U_bernoulli")
    out["U_over_V"] = U / V if U is not None and V else None
    out["U_over_U_bernoulli"] = U / UB if U is not None and UB else None
    return out


def fit_rates(results):
    """U = a + b V over the finished runs with a steady rate: a, b and their standard errors (the least-
    squares covariance scaled by the residual variance; none from two points), the runs left out
    and why."""
    use = [r for r in results if r.get("U") is not None and r["status"] == "finished"]
    left = [{"run": r["run"], "why": f"the run is {r['status']}" if r["status"] != "finished"
             else next((x for x in r["notes"] if "steady" in x), "no steady rate")}
            for r in results if r not in use]
    V = np.array([r["V"] for r in use])
    if len(use) < 2 or np.ptp(V) <= 0.0:
        return {"a": None, "b": None, "runs": len(use), "left_out": left,
                "why": "fewer than two speeds with a steady rate"}
    U = np.array([r["U"] for r in use])
    A = np.vstack([np.ones_like(V), V]).T
    coef, *_ = np.linalg.lstsq(A, U, rcond=None)
    fit = {"a": float(coef[0]), "b": float(coef[1]), "runs": len(use), "left_out": left,
           "a_error": None, "b_error": None}
    if len(use) >= 3:
        res = U - A @ coef
        s2 = float(res @ res) / (len(use) - 2)
        cov = s2 * np.linalg.inv(A.T @ A)
        fit["a_error"], fit["b_error"] = float(math.sqrt(cov[0, 0])), float(math.sqrt(cov[1, 1]))
    else:
        fit["why"] = "two runs: a line through them, no uncertainty"
    return fit


def jsonable(x):
    """NaN and inf as None, numpy scalars and arrays as Python's: json.dumps gives valid JSON."""
    if isinstance(x, dict):
        return {k: jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return jsonable(x.tolist())
    if isinstance(x, (np.floating, float)):
        return float(x) if math.isfinite(x) else None
    if isinstance(x, np.integer):
        return int(x)
    if isinstance(x, np.bool_):
        return bool(x)
    return x


__all__ = ["analyse", "fit_rates", "tate", "tate_rate", "tate_strengths", "lanz_odermatt",
           "bernoulli_rate", "steady_window", "arrest", "jsonable"]
