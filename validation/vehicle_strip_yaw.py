"""The strip contact under the wheelset's yaw against a brute-force search over the 3-D wheel.

With a yaw psi of the wheelset against the rail the contact of a wheel (a surface of
revolution about the yawed axle) on the rail (its profile extruded along the track) moves
ahead of or behind the wheel's lowest point, and the wheel's lateral arm shortens by
cos(psi). The strip contact (railvti.vehicle.strip, Fortran vehicle_strip: ring_deepest)
finds, for each wheel-profile sample, the deepest point of its circle by Newton's method in
the circle's angle. The reference here is independent of that code: each wheel-profile
point is turned through a grid of angles about the axle, rolled and yawed by rotation
matrices and set over the rail profile's height (railvti.profiles.Profile.height), the
deepest point kept (601 angles over +-0.12 rad, refined four times).

For the left wheel on the tread (y = 0) and on the flange (y = 7 mm), at yaw 0..10 mrad and
zero roll, the centre height is set so that the strips' largest interference is 2 um (light
contact: the patch shrinks to the deepest point). Printed: the gap the yaw closes (how far
the centre must rise to keep that contact: on the flange the lead deepens the contact by
about r theta^2 / 2 while the shortened arm moves the wheel off the gauge face), the strips' and the
brute force's largest interference on the strips' own samples (0.2 mm) and on a 10x finer
grid (the sampling's own error), the contact's track x (strips: load-weighted; brute force:
deepest point) and its lead ahead of the wheel's lowest point. Writes
validation/figures/vehicle_strip_yaw.png.

Run: python validation/vehicle_strip_yaw.py      (~30 s)
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from railvti.vehicle import systems
from railvti.geometry import layout
from railvti.vehicle.strip import STRIP_OUTPUTS, strip_geometry, strip_wheel

FIG = Path(__file__).resolve().parent / "figures" / "vehicle_strip_yaw.png"
N, PM, XC = (STRIP_OUTPUTS.index(k) for k in ("N", "P_max", "xc"))
STEP = 2e-4
CASES = (("tread", 0.0, (-0.01, 0.01)), ("flange", 7e-3, (-0.045, -0.02)))


def brute_force(wheel, rail, y, zc, roll, yaw, s):
    """(P, x, s) of the deepest point of the wheel points s (profile coordinates) over the
    rail, each point's circle searched on an angle grid (as tests/test_vehicle_strip_yaw.py)."""
    lay = layout(wheel, rail)
    r = lay.wheelset.wheel_radius + wheel.height(s)
    y0 = lay.wheelset.contact_y + s
    cr, sr, cy, sy = np.cos(roll), np.sin(roll), np.cos(yaw), np.sin(yaw)
    rot = np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]]) @ np.array(
        [[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]]
    )

    def interference(th):
        pts = np.stack([r * np.sin(th), np.broadcast_to(y0, th.shape), -r * np.cos(th)])
        x, yy, z = np.einsum("ij,j...->i...", rot, pts)
        yl = y + yy - lay.rail_offset
        h = lay.rail_top - rail.height(np.clip(yl, rail.y_min, rail.y_max))
        p = h - (lay.wheelset.wheel_radius + zc + z)
        return np.where((yl >= rail.y_min) & (yl <= rail.y_max), p, -np.inf), x

    cols = np.arange(s.size)
    th = np.broadcast_to(np.linspace(-0.12, 0.12, 601)[:, None], (601, s.size))
    for _ in range(4):
        p, x = interference(th)
        k = p.argmax(axis=0)
        step = th[1, 0] - th[0, 0]
        th = th[k, cols][None, :] + np.linspace(-step, step, 41)[:, None]
    p, x = interference(th)
    k = p.argmax(axis=0)
    pj, xj = p[k, cols], x[k, cols]
    j = int(pj.argmax())
    return pj[j], xj[j], s[j]


def light_contact(geo, y, yaw, pmax=2e-6):
    """Centre height (m) at which the strips' largest interference is pmax."""
    lo, hi = -0.02, 0.02
    for _ in range(60):
        zc = 0.5 * (lo + hi)
        out, _ = strip_wheel(geo, y, zc, 0.0, yaw)
        lo, hi = (zc, hi) if out[:, PM].max() > pmax else (lo, zc)
    return zc


def main() -> None:
    wheel, rail = systems.profiles()
    geo = strip_geometry(wheel, rail, step=STEP)
    lay = layout(wheel, rail)
    grid = np.arange(wheel.y_min, wheel.y_max + 1e-12, STEP)
    yaws = np.linspace(0.0, 10e-3, 11)
    res = {}
    print("left wheel, zero roll, light contact (strips' largest interference 2 um)")
    print(
        f"{'case':>7s} {'yaw':>5s} {'gap closed':>10s} {'P strips':>9s} {'P brute':>9s} "
        f"{'P brute fine':>12s} {'x strips':>9s} {'x brute':>9s} {'lead strips':>11s} {'lead brute':>10s}"
    )
    print(
        f"{'':>7s} {'mrad':>5s} {'um':>10s} {'um':>9s} {'um':>9s} {'um':>12s} {'mm':>9s} {'mm':>9s} "
        f"{'mm':>11s} {'mm':>10s}"
    )
    for name, y, (lo, hi) in CASES:
        s = grid[(grid >= lo) & (grid <= hi)]
        fine = np.arange(lo, hi, STEP / 10)
        rows = []
        z0 = None
        for yaw in yaws:
            zc = light_contact(geo, y, yaw)
            z0 = zc if z0 is None else z0
            out, _ = strip_wheel(geo, y, zc, 0.0, yaw)
            k = int(out[:, N].argmax())
            pb, xb, sb = brute_force(wheel, rail, y, zc, 0.0, yaw, s)
            pf, _, _ = brute_force(wheel, rail, y, zc, 0.0, yaw, fine)
            # the lead ahead of the wheel's lowest point: x + y0 tan(psi) at the deepest point
            arm = lay.wheelset.contact_y + sb
            row = dict(
                yaw=yaw,
                gap=zc - z0,
                ps=out[:, PM].max(),
                pb=pb,
                pf=pf,
                xs=out[k, XC],
                xb=xb,
                ls=out[k, XC] + arm * np.tan(yaw),
                lb=xb + arm * np.tan(yaw),
            )
            rows.append(row)
            if round(yaw * 1e3) in (0, 2, 5, 10):
                print(
                    f"{name:>7s} {yaw * 1e3:5.0f} {row['gap'] * 1e6:10.2f} {row['ps'] * 1e6:9.4f} "
                    f"{row['pb'] * 1e6:9.4f} {row['pf'] * 1e6:12.4f} {row['xs'] * 1e3:9.4f} "
                    f"{row['xb'] * 1e3:9.4f} {row['ls'] * 1e3:11.3f} {row['lb'] * 1e3:10.3f}"
                )
        res[name] = rows
    for name in res:
        d = max(abs(r["ps"] - r["pb"]) for r in res[name])
        dx = max(abs(r["xs"] - r["xb"]) for r in res[name])
        df = max(r["pf"] - r["ps"] for r in res[name])
        print(
            f"{name}: strips against brute force on the same samples: interference within "
            f"{d * 1e9:.2f} nm, contact x within {dx * 1e6:.1f} um; the 10x finer grid finds up to "
            f"{df * 1e6:.3f} um more interference (the 0.2 mm sampling's own error)"
        )
    plot(res)


def plot(res: dict) -> None:
    """Gap change and lead against yaw, strips (lines) and brute force (markers)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    for (name, rows), col in zip(res.items(), ("C0", "C3")):
        yaw = np.array([r["yaw"] for r in rows]) * 1e3
        ax[0].plot(yaw, [r["gap"] * 1e6 for r in rows], color=col, label=f"{name}: strips")
        # the brute force's: the strips' centre rise plus what the brute force finds beyond 2 um
        ax[0].plot(
            yaw,
            [(r["gap"] + r["pb"] - r["ps"]) * 1e6 for r in rows],
            "o",
            color=col,
            mfc="none",
            label=f"{name}: brute force",
        )
        ax[1].plot(yaw, [r["ls"] * 1e3 for r in rows], color=col, label=f"{name}: strips (load-weighted)")
        ax[1].plot(
            yaw,
            [r["lb"] * 1e3 for r in rows],
            "o",
            color=col,
            mfc="none",
            label=f"{name}: brute force (deepest point)",
        )
    ax[0].set_xlabel("yaw of the wheelset against the rail, mrad")
    ax[0].set_ylabel("vertical gap closed by the yaw, um")
    ax[0].set_title("Gap change at 2 um contact (S1002 / UIC60 1:40, left wheel)")
    ax[1].set_xlabel("yaw of the wheelset against the rail, mrad")
    ax[1].set_ylabel("contact ahead of the wheel's lowest point, mm")
    ax[1].set_title("Longitudinal contact position (lead)")
    for a in ax:
        a.grid(alpha=0.3)
        a.legend(fontsize=8)
    fig.tight_layout()
    FIG.parent.mkdir(exist_ok=True)
    fig.savefig(FIG, dpi=120)
    print(f"wrote {FIG}")


if __name__ == "__main__":
    main()
