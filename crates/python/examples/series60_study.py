"""A design study on Dask: the Series 60 Cb 0.60 parent transformed in L/B and B/T, every
variant fitted by hullskin, tabulated (particulars, fit errors, fairness, hydrostatics) and
plotted.

    python crates/python/examples/series60_study.py [--scheduler ADDRESS] [--grid N M] [--out DIR]

Without --scheduler a LocalCluster of 2 worker processes runs the fits; with it, any Dask
cluster does (SLURM, Kubernetes: crates/python/README.md). Writes study.csv and study.png.
"""

import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from hullskin import study  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scheduler", help="address of a running Dask scheduler (default: a LocalCluster)")
    parser.add_argument("--grid", type=int, nargs=2, default=(15, 14), metavar=("N_LB", "N_BT"),
                        help="variants in L/B (5.5 to 8.5) and B/T (2 to 3.5); default 15 x 14 = 210")
    parser.add_argument("--out", default="hullskin-out/study")
    args = parser.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    from dask.distributed import Client, LocalCluster

    variants = study.series60_variants(np.linspace(5.5, 8.5, args.grid[0]), np.linspace(2.0, 3.5, args.grid[1]))
    if args.scheduler:
        client, cluster = Client(args.scheduler), None
    else:
        cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
        client = Client(cluster)
    try:
        df = study.run(variants, client=client)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()

    df.to_csv(out / "study.csv", index=False)
    failed = df[df["error"] != ""]
    print(f"{len(df)} variants, {len(failed)} failed, on workers {df.attrs['workers']}")
    cols = ["name", "l_over_b", "b_over_t", "max_error", "rms_error", "thin_plate", "displ", "cb", "s", "kmt"]
    print(df[cols].to_string(index=False, float_format=lambda x: f"{x:.4g}"))

    ok = df[df["error"] == ""]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    # One line per B/T (its computed value carries the scale factors' rounding).
    for bt, g in ok.groupby(ok["b_over_t"].round(6)):
        axes[0].plot(g["l_over_b"], g["kmt"], "-o", ms=3, label=f"B/T {bt:.2f}")
        axes[1].plot(g["l_over_b"], 1000 * g["max_error"], "-o", ms=3)
    axes[0].set_xlabel("L/B")
    axes[0].set_ylabel("KMt (m)")
    axes[0].legend(fontsize=6, ncol=2)
    axes[1].set_xlabel("L/B")
    axes[1].set_ylabel("max fit error (mm)")
    fig.suptitle("Series 60 Cb 0.60 parent transformed: hullskin fits on Dask")
    fig.tight_layout()
    fig.savefig(out / "study.png", dpi=120)
    print(f"wrote {out / 'study.csv'} and {out / 'study.png'}")


if __name__ == "__main__":
    main()
