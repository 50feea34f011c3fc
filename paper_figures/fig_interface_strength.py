"""Seed 001 Figs. 5, 8-10, A1, A4 style: strength domains of the fibre (spring grid) interface.

Reads only ``validation/results/interface-strength.json`` and ``interface-strength.npz`` (run
``python -m validation run interface-strength --quick`` first); never solves. Writes
``paper_figures/out/fig_interface_strength.png`` (six panels) and
``paper_figures/out/fig_interface_strength_alpha.png`` (normalised domains vs Table A1).
"""

from __future__ import annotations

import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from validation.report import reading_dir

RESULTS = reading_dir()  # validation/results, or BLOCKMECH_RESULTS (quick or a path)
OUT = Path(__file__).resolve().parent / "out"
CASE = "interface-strength"
RATIOS = (0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0)
COLUMNS = (
    ("f1", "f1", r"shear $f_1$"),
    ("f2", "f2", r"shear $f_2$"),
    ("f1=f2", "f1eqf2", r"$d_1 = d_2$ ('$f_1 = f_2$')"),
)


def _law(f: np.ndarray, alpha: float) -> np.ndarray:
    return (1.0 - np.clip(f, 0.0, 1.0) ** 2) ** (1.0 / alpha)


def _rows(data: dict) -> dict[str, dict]:
    return {r["quantity"]: r for r in data["rows"]}


def _panel_shear(ax_curve, ax_domain, c: dict, f_su: float) -> None:
    for tag, style in (("d1", "-"), ("d2", "--")):
        ax_curve.plot(
            c[f"fig5_{tag}_disp"] * 1e3, c[f"fig5_{tag}_force"], style, label=f"sliding along {tag}"
        )
    ax_curve.set_xlabel("relative sliding [mm]")
    ax_curve.set_ylabel("shear force [N]")
    ax_curve.set_title("shear: incremental curves (Fig. 5)")
    ax_curve.legend(fontsize=7)
    th = np.linspace(0.0, 2.0 * np.pi, 200)
    ax_domain.plot(f_su * np.cos(th), f_su * np.sin(th), "k--", lw=0.8, label=r"$|f| = \mu|N|$")
    ax_domain.plot(c["fig5_domain_f1"], c["fig5_domain_f2"], "o", ms=3, label="EPP end points")
    ax_domain.set_aspect("equal")
    ax_domain.set_xlabel(r"$f_1$ [N]")
    ax_domain.set_ylabel(r"$f_2$ [N]")
    ax_domain.set_title("shear domain (Fig. 5)")
    ax_domain.legend(fontsize=7, loc="center")


def _panel_fig8(ax, c, m3u: float, f_su: float) -> None:
    ax.plot(c["fig8_domain_f1"], c["fig8_domain_m3"], "k-", lw=1.5, label="spring grid (exact)")
    f = np.linspace(0.0, 1.0, 200)
    ax.plot(f * f_su, np.sqrt(1.0 - f**2) * m3u, "k--", lw=0.8, label="circle")
    for k in range(len(c["fig8_epp_rho"])):
        lab = "EPP paths" if k == 0 else None
        ax.plot(
            c[f"fig8_epp{k}_f1"],
            c[f"fig8_epp{k}_m3"],
            "-",
            color="C0",
            lw=0.7,
            alpha=0.7,
            label=lab,
        )
        ax.plot(c[f"fig8_epp{k}_f1"][-1], c[f"fig8_epp{k}_m3"][-1], "o", color="C0", ms=3)
    ax.set_xlabel(r"$f_1$ [N]")
    ax.set_ylabel(r"$m_3$ [N m]")
    ax.set_title(r"$m_3$-$f_1$ domain, seed interface (Fig. 8)")
    ax.legend(fontsize=7)


def _panel_fig10(ax, c) -> None:
    for tag, col, lab in (
        ("m1", "C0", r"$m_1$ ($m_2=0$)"),
        ("m2", "C1", r"$m_2$ ($m_1=0$)"),
        ("m1m2", "C2", r"$m_1$, $m_2$ proportional"),
    ):
        x = np.hypot(c[f"fig10_{tag}_m1"], c[f"fig10_{tag}_m2"])
        ax.step(x, c[f"fig10_{tag}_spring"], where="mid", color=col, lw=1.0, label=lab)
        ax.plot(x, c[f"fig10_{tag}_closed"], "--", color=col, lw=0.8)
        if f"fig10_{tag}_elastic" in c:
            ax.plot(x, c[f"fig10_{tag}_elastic"], ":", color=col, lw=1.2)
    ax.set_xlabel(r"bending moment $\sqrt{m_1^2 + m_2^2}$ [N m]")
    ax.set_ylabel(r"torsion strength $m_{3,u}$ [N m]")
    ax.set_title(
        "torsion vs bending (Fig. 10)\ndashed: closed form; dotted: elastic no-tension pressure",
        fontsize=9,
    )
    ax.legend(fontsize=7)


def _panel_a1(ax, c) -> None:
    s = c["figA1_sigma_t"] / 1e3
    ax.plot(s, c["figA1_spring"], "-", label="spring grid 32x32")
    ax.plot(s, c["figA1_eq12"], "k--", lw=0.8, label="Eq. (12), closed-form $c_T$")
    ax.set_xlabel(r"tensile strength $\bar\sigma_t$ [kPa] ($c = \mu\bar\sigma_t$)")
    ax.set_ylabel(r"$m_{3,u}$ [N m]")
    ax.set_title("torsion vs tensile strength (Fig. A1)")
    ax.legend(fontsize=7)


def _panel_convergence(ax, rows: dict) -> None:
    pts = [
        (int(q.split()[3].split("x")[0]), r["rel_error"])
        for q, r in rows.items()
        if q.startswith("c_T spring grid")
    ]
    n, err = np.array(pts, dtype=float).T
    ax.loglog(n, err, "o-", label="spring grid vs closed form")
    ax.loglog(n, err[0] * (n[0] / n) ** 2, "k--", lw=0.8, label=r"$O(n^{-2})$")
    order = rows["c_T convergence order (fit over grids >= 16)"]["ours"]
    ax.set_xlabel("springs per side n")
    ax.set_ylabel(r"relative error of $c_T$")
    ax.set_title(f"torsion coefficient, observed order {order:.2f}")
    ax.legend(fontsize=7)


def _alpha_figure(c, rows: dict) -> Path:
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.3), sharey=True)
    cmap = plt.get_cmap("viridis")
    for ax, (label, key, title) in zip(axes, COLUMNS, strict=True):
        for k, ratio in enumerate(RATIOS):
            row = rows[f"alpha, l1/l2 = {ratio:g}, shear {label}"]
            col = cmap(k / (len(RATIOS) - 1))
            f, m = c[f"alpha_r{ratio:g}_{key}_f"], c[f"alpha_r{ratio:g}_{key}_m"]
            ax.plot(
                f,
                m,
                "-",
                color=col,
                lw=1.4,
                label=rf"$l_1/l_2$={ratio:g}: $\alpha$={row['ours']:.2f} "
                f"(seed {row['reference']['value']:.2f})",
            )
            ax.plot(f, _law(f, row["reference"]["value"]), ":", color=col, lw=1.0)
        ax.set_title(f"{title}; dotted: Eq. (A5) with Table A1")
        ax.set_xlabel(r"$f/f_{s,u}$")
        ax.set_xlim(0, 1.02)
        ax.set_ylim(0, 1.02)
        ax.legend(fontsize=6.5, loc="lower left")
    axes[0].set_ylabel(r"$m_3/m_{3,u}$")
    fig.tight_layout()
    path = OUT / "fig_interface_strength_alpha.png"
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return path


def main() -> list[Path]:
    """Draw the figures from the stored results and return their paths."""
    for name in (f"{CASE}.json", f"{CASE}.npz"):
        if not (RESULTS / name).exists():
            raise FileNotFoundError(
                f"{RESULTS / name} is missing: run 'python -m validation run {CASE} --quick' first"
            )
    data = json.loads((RESULTS / f"{CASE}.json").read_text())
    rows = _rows(data)
    OUT.mkdir(parents=True, exist_ok=True)
    with np.load(RESULTS / f"{CASE}.npz") as c:
        curves = {k: c[k] for k in c.files}
    f_su = rows["shear strength f_su, seed interface [N]"]["ours"]
    m3u = rows["pure torsion strength m3u, seed interface [N m]"]["ours"]
    fig, axes = plt.subplots(2, 3, figsize=(14, 8.5))
    _panel_shear(axes[0, 0], axes[0, 1], curves, f_su)
    _panel_fig8(axes[0, 2], curves, m3u, f_su)
    _panel_fig10(axes[1, 0], curves)
    _panel_a1(axes[1, 1], curves)
    _panel_convergence(axes[1, 2], rows)
    fig.suptitle("Interface 0.3 x 0.2 m, N = -240 N, mu = 0.7, 32 x 32 springs (seed 001 Sec. 2.1)")
    fig.tight_layout()
    path = OUT / "fig_interface_strength.png"
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return [path, _alpha_figure(curves, rows)]


if __name__ == "__main__":
    for p in main():
        print(p)
