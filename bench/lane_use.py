#!/usr/bin/env python3
"""How full the pair loop's vectors are, and how full a cluster-pair loop's would be, on a frame.

    python3 bench/lane_use.py FRAME.npz DX [--lanes 8] [--support 2.6]

FRAME.npz is a frame of a sluice run (2D or 3D), DX its particle spacing; the support radius is
SUPPORT x DX (2.6: h = 1.3 dx and a kernel of support 2h). Prints, per particle:

- the useful pairs: those within the support with a fluid particle on either side, each once;
- sluice's pair loop as physics/pair_loop-inl.hpp traverses them: cells the support wide, sorted
  x fastest; each particle takes the rest of its cell and of the next cell along x, and the rows of
  three cells above it (2D) or the next row and the three rows of the next plane (3D), a vector of
  LANES consecutive candidates at a time from each range's start (from i + 1's vector in its own
  cell); a vector is tested, and evaluated if it holds a neighbour; a wall particle's ranges
  without fluid are not tested;
- the alternative of GROMACS's cluster pairs (nbnxm): columns W x DX wide along x (2D) or in x-y
  (3D), particles sorted along the last axis within each column, fluid and wall apart, clusters of
  M consecutive particles, and every pair of clusters whose bounding boxes come within the support
  (not both wall) evaluated whole, M x M lanes, plus each cluster with itself.

The lane use is the useful pairs over the lanes evaluated. Needs NumPy and SciPy (python3-scipy).
"""
import argparse

import numpy as np
from scipy.spatial import cKDTree


def useful_pairs(x, fluid, radius):
    pairs = cKDTree(x).query_pairs(radius, output_type="ndarray")
    return int((fluid[pairs[:, 0]] | fluid[pairs[:, 1]]).sum())


def present_loop(x, fluid, radius, lanes):
    dim = x.shape[1]
    lo = x.min(0) - 1e-9
    c = np.floor((x - lo) / radius).astype(int)
    dims = c.max(0) + 1
    stride = np.cumprod(np.r_[1, dims[:-1]])
    cell = (c * stride).sum(1)
    order = np.argsort(cell, kind="stable")
    xs, fl, cs = x[order], fluid[order], cell[order]
    start = np.searchsorted(cs, np.arange(np.prod(dims) + 1))
    fluid_before = np.r_[0, np.cumsum(fl)]
    index = lambda cc: int((np.asarray(cc) * stride).sum())
    rows = [(1,)] if dim == 2 else [(1, 0), (-1, 1), (0, 1), (1, 1)]
    tested = evaluated = used = 0
    for ci in np.unique(cs):
        cc = np.array([(ci // stride[d]) % dims[d] for d in range(dim)])
        b, e = start[ci], start[ci + 1]
        own_end = start[index([min(cc[0] + 1, dims[0] - 1)] + list(cc[1:])) + 1]
        others = []
        for o in rows:
            rc = cc[1:] + np.array(o)
            if np.any(rc < 0) or np.any(rc >= dims[1:]):
                continue
            first = index([max(cc[0] - 1, 0)] + list(rc))
            last = index([min(cc[0] + 1, dims[0] - 1)] + list(rc))
            others.append((start[first], start[last + 1]))
        for i in range(b, e):
            ranges = [(b + (i + 1 - b) // lanes * lanes, own_end, True)] + [(p, q, False) for p, q in others]
            for p, q, own in ranges:
                if not fl[i] and fluid_before[q] == fluid_before[i + 1 if own else p]:
                    continue
                for j in range(p, q, lanes):
                    js = np.arange(j, min(j + lanes, q))
                    if own:
                        js = js[js > i]
                    if len(js) == 0:
                        continue
                    r2 = ((xs[js] - xs[i]) ** 2).sum(1)
                    hit = (r2 < radius * radius) & (r2 > 0)
                    if not fl[i]:
                        hit &= fl[js]
                    tested += 1
                    if hit.any():
                        evaluated += 1
                        used += int(hit.sum())
    return tested, evaluated, used


def cluster_pairs(x, fluid, radius, width, m):
    dim = x.shape[1]
    n = len(x)
    lo = x.min(0)
    col = np.floor((x[:, : dim - 1] - lo[: dim - 1]) / width).astype(int)
    column = col[:, 0] if dim == 2 else col[:, 0] * (col[:, 1].max() + 1) + col[:, 1]
    order = np.lexsort((x[:, dim - 1], (~fluid).astype(int), column))
    columns, fl, xs = column[order], fluid[order], x[order]
    clusters = []
    i = 0
    while i < n:
        j = i
        while j < n and j - i < m and columns[j] == columns[i] and fl[j] == fl[i]:
            j += 1
        clusters.append((i, j))
        i = j
    low = np.array([xs[a:b].min(0) for a, b in clusters])
    high = np.array([xs[a:b].max(0) for a, b in clusters])
    wet = np.array([fl[a:b].any() for a, b in clusters])
    centre = (low + high) / 2
    reach = np.sqrt((((high - low) / 2) ** 2).sum(1)).max()
    near = cKDTree(centre).query_pairs(radius + 2 * reach, output_type="ndarray")
    a, b = near[:, 0], near[:, 1]
    gap = np.maximum(0.0, np.maximum(low[a] - high[b], low[b] - high[a]))
    pairs = int((((gap**2).sum(1) < radius * radius) & (wet[a] | wet[b])).sum()) + int(wet.sum())
    return len(clusters), pairs * m * m


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("frame")
    parser.add_argument("dx", type=float)
    parser.add_argument("--lanes", type=int, default=8, help="doubles per vector (8: AVX-512, 4: AVX2)")
    parser.add_argument("--support", type=float, default=2.6, help="support radius in spacings")
    args = parser.parse_args()
    frame = np.load(args.frame)
    x = np.asarray(frame["x"], dtype=float)
    fluid = np.asarray(frame["kind"]) == 0
    n = len(x)
    radius = args.support * args.dx
    useful = useful_pairs(x, fluid, radius)
    print(f"{x.shape[1]}D frame, {n} particles ({int(fluid.sum())} fluid), support {radius:g} m: "
          f"{useful / n:.2f} useful pairs per particle")
    tested, evaluated, used = present_loop(x, fluid, radius, args.lanes)
    print(f"pair loop, {args.lanes} lanes: {tested / n:.2f} vectors tested and {evaluated / n:.2f} evaluated per "
          f"particle, {used / evaluated:.2f} of {args.lanes} lanes used; lane use {useful / (evaluated * args.lanes):.2f}")
    for width in (1.5, 2.0):
        for m in (4, 8):
            count, lanes = cluster_pairs(x, fluid, radius, width * args.dx, m)
            print(f"cluster pairs, columns {width:g} dx, clusters of {m} ({n / count:.2f} particles each): "
                  f"{lanes / n:.1f} lanes evaluated per particle; lane use {useful / lanes:.2f}")


if __name__ == "__main__":
    main()
