#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""A small convergence study through the Python module: the generator's surface of a job against
the OpenVDB reference at several voxel sizes, with numpy statistics of the per-sample deviations,
and a plot when matplotlib is installed (as in a notebook).

    PYTHONPATH=build/python python3 examples/deviation_study.py data/jobs/single_slot.json \
        --voxels 0.5,0.35,0.25 --plot out/study.png
"""
import argparse
import math
import sys

import numpy as np

import morphmill


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("job")
    parser.add_argument("--voxels", default="0.5,0.35,0.25", help="reference voxel sizes, job units")
    parser.add_argument("--samples", type=int, default=20000, help="face samples per surface")
    parser.add_argument("--plot", help="PNG of the deviation against the voxel size (needs matplotlib)")
    args = parser.parse_args()

    job = morphmill.load_job(args.job)
    part = morphmill.erode(job)
    print(f"{job.name}: generator {part.mesh.triangle_count} triangles, volume {part.topology.volume:.4f} "
          f"{job.units}^3, valid {part.valid}")
    rows = []
    for voxel in (float(v) for v in args.voxels.split(",")):
        reference = morphmill.reference(job, voxel_size=voxel)
        d = morphmill.deviation(part.mesh, reference.mesh, face_samples=args.samples)
        values = np.abs(np.concatenate([d.a_to_b.values, d.b_to_a.values]))
        bound = job.tolerance + math.sqrt(3) * voxel  # what verify allows between the two
        rows.append((voxel, d.hausdorff, float(np.percentile(values, 99)), float(values.mean()), bound,
                     reference.volume))
    print(f"{'voxel':>8} {'hausdorff':>10} {'p99':>8} {'mean':>8} {'bound':>8} {'ref volume':>12}")
    for voxel, hausdorff, p99, mean, bound, volume in rows:
        print(f"{voxel:8.3f} {hausdorff:10.4f} {p99:8.4f} {mean:8.4f} {bound:8.4f} {volume:12.4f}")
    converges = all(hausdorff <= bound for _, hausdorff, _, _, bound, _ in rows)
    print("converges: " + ("yes" if converges else "no") + " (every Hausdorff distance within its bound)")

    if args.plot:
        try:
            import matplotlib
            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
        except ImportError:
            print("--plot: matplotlib is not installed", file=sys.stderr)
            return 2
        voxels = [r[0] for r in rows]
        plt.loglog(voxels, [r[1] for r in rows], "o-", label="Hausdorff")
        plt.loglog(voxels, [r[2] for r in rows], "s-", label="p99 |deviation|")
        plt.loglog(voxels, [r[4] for r in rows], "k--", label="bound")
        plt.xlabel(f"voxel size ({job.units})")
        plt.ylabel(f"deviation ({job.units})")
        plt.legend()
        plt.savefig(args.plot, dpi=120)
        print(f"wrote {args.plot}")
    return 0 if converges else 1


if __name__ == "__main__":
    sys.exit(main())
