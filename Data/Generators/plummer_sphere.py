#!/usr/bin/python3
"""Sample the particles of a Plummer sphere (a model star cluster) and write
them as legacy VTK binary polydata, in chunks, so that 1e8 particles fit in
a few GB of memory.

Usage: plummer_sphere.py [--n N] [--seed S] [--a A] [--rmax R] [--k K] [--c C]
                         OUTPUT.vtk

The model (Plummer 1911), in N-body units G = M = 1 with scale length a
(default a = 1, i.e. lengths are in units of the scale length, not the
virial radius: the virial radius is 16 a / (3 pi) = 1.698 a; --a 0.5890486
(3 pi / 16) gives Henon's standard units with virial radius 1):
  density    rho(r) = 3 M / (4 pi a^3) (1 + r^2 / a^2)^(-5/2)
  mass       M(r) / M = r^3 / (r^2 + a^2)^(3/2)
  potential  Phi(r) = -G M / sqrt(r^2 + a^2), v_esc = sqrt(2 G M) (r^2 + a^2)^(-1/4)
The sampling is the recipe of Aarseth, Henon & Wielen (1974), A&A 37, 183,
"A comparison of numerical methods for the study of star cluster dynamics",
Appendix, written here from the formulas above:
  radius     r = a / sqrt(X^(-2/3) - 1), X uniform in (0, 1], inverting M(r).
             The model has infinite extent; a radius beyond rmax = 20 a
             (0.37 % of the mass) is redrawn, so the radii follow the profile
             truncated at 20 a and the file has exactly N particles. The
             number redrawn is printed.
  position   the radius times an isotropic direction (cos(theta) uniform in
             [-1, 1], phi uniform in [0, 2 pi)).
  speed      v = q v_esc(r), q in [0, 1) from the isotropic distribution
             function f(E) ~ (-E)^(7/2), i.e. g(q) ~ q^2 (1 - q^2)^(7/2),
             drawn by von Neumann rejection: q and y uniform in [0, 1) and
             [0, 0.1) (max g = 0.0923 at q^2 = 2/9), keep q if y < g(q).
             Velocities at each radius follow the untruncated model's f(E).
Only the speed is written (no velocity vectors), so no velocity direction
is drawn.

Output, in N-body units (G = M = 1, lengths in a): float points (the
cluster centre is the origin), one VERTEX cell per particle (exactly as
lammps_dump_to_vtk.py's write_vtk writes them), and the float point arrays,
in this order:
  speed   |v|; the active scalars, so a plain reader colours by it
  radius  a sphere radius for rendering, from the local density:
          h = c (3 k m / (4 pi rho(r)))^(1/3) = c a (k / N)^(1/3) (1 + r^2/a^2)^(5/6)
          with m = M / N, k = 1 and c = 0.5. (3 m / (4 pi rho))^(1/3) = s is
          the radius of the sphere holding one particle's share of the
          volume; the mean nearest-neighbour distance of a random (Poisson)
          field of that density is Gamma(4/3) s = 0.893 s, so spheres of
          diameter 2 h = s roughly touch their nearest neighbours, and they
          fill 1/8 of the volume locally (overlaps counted twice).
  mass    M / N (equal masses)
Points are in sampling order (random). The random seed is fixed (--seed,
default 1): one numpy Generator, np.random.default_rng(seed), draws every
chunk in turn; the chunk size is fixed, so the same N and seed give a
byte-identical file.

Memory: the points are written chunk by chunk while they are sampled
(5,000,000 particles per chunk); speed and radius are kept as float32
(8 bytes a particle, 0.8 GB at 1e8) to be written after the points and
VERTICES sections. Legacy VTK stores the VERTICES connectivity as int32
and its size, 2 N, must fit too, so N is at most 1,073,741,823.
Legacy .vtk is used because Debian 12's VTK fails on XML files with
appended data (see SETUP.md). Run with Debian's /usr/bin/python3 (numpy).
"""

import argparse
import math
import sys
import time

import numpy as np

DEFAULT_N = 1_000_000
DEFAULT_SEED = 1
DEFAULT_A = 1.0
DEFAULT_RMAX_OVER_A = 20.0
DEFAULT_K = 1
DEFAULT_C = 0.5
CHUNK = 5_000_000
MAX_N = (2**31 - 1) // 2  # VERTICES: 2 N int32 values, indices < N
G_MAX = 0.1  # bound of g(q) = q^2 (1 - q^2)^(7/2) for the rejection (max 0.0923)


def mass_fraction(x):
    """M(r) / M at r = x a."""
    return x**3 / (1.0 + x * x) ** 1.5


def expected_half_mass_radius(rmax_over_a):
    """Half-mass radius / a of the profile truncated at rmax (1.305 untruncated)."""
    y = (0.5 * mass_fraction(rmax_over_a)) ** (2.0 / 3.0)
    return math.sqrt(y / (1.0 - y))


def expected_mean_v2(rmax_over_a):
    """Mass-weighted <v^2> / (G M / a) of the truncated sample (3 pi / 32 untruncated).

    At radius r, <v^2> = <q^2> v_esc^2 = v_esc^2 / 4 = (G M / a) / (2 sqrt(1 + r^2/a^2))
    (<q^2> = B(5/2, 9/2) / B(3/2, 9/2) = 1/4); averaged over dM = 3 M s^2 (1 + s^2)^(-5/2) ds
    this is 3/2 int_0^x s^2 (1 + s^2)^(-3) ds / M(x), and with s = tan(t) the integral is
    t/8 - sin(4 t)/32, pi/16 for x -> infinity.
    """
    t = math.atan(rmax_over_a)
    return 1.5 * (t / 8.0 - math.sin(4.0 * t) / 32.0) / mass_fraction(rmax_over_a)


def sample_radii(rng, m, a):
    """m radii from the untruncated Plummer mass profile."""
    x = 1.0 - rng.random(m)  # (0, 1]; X = 1 gives r = inf, which is redrawn
    with np.errstate(divide="ignore"):
        return a / np.sqrt(x ** (-2.0 / 3.0) - 1.0)


def sample_q(rng, m):
    """m values of q = v / v_esc with density ~ q^2 (1 - q^2)^(7/2), by rejection."""
    q = np.empty(m)
    filled = 0
    while filled < m:
        need = m - filled
        # The acceptance rate is 0.43 (int g dq = B(3/2, 9/2) / 2 = 0.0430, over 0.1).
        trial = int(need * 2.5) + 64
        qq = rng.random(trial)
        y = rng.random(trial) * G_MAX
        q2 = qq * qq
        accepted = qq[y < q2 * (1.0 - q2) ** 3.5]
        take = min(need, len(accepted))
        q[filled:filled + take] = accepted[:take]
        filled += take
    return q


def sample_chunk(rng, m, a, rmax):
    """m particles: (xyz float64 (m, 3), speed, r, number of radii redrawn)."""
    r = sample_radii(rng, m, a)
    redrawn = 0
    bad = np.flatnonzero(~(r <= rmax))
    while len(bad):
        redrawn += len(bad)
        r[bad] = sample_radii(rng, len(bad), a)
        bad = bad[~(r[bad] <= rmax)]
    cos_t = rng.uniform(-1.0, 1.0, m)
    phi = rng.uniform(0.0, 2.0 * np.pi, m)
    sin_t = np.sqrt(1.0 - cos_t * cos_t)
    xyz = np.empty((m, 3))
    xyz[:, 0] = r * sin_t * np.cos(phi)
    xyz[:, 1] = r * sin_t * np.sin(phi)
    xyz[:, 2] = r * cos_t
    # G = M = 1: v_esc = sqrt(2) (r^2 + a^2)^(-1/4).
    speed = sample_q(rng, m) * np.sqrt(2.0) * (r * r + a * a) ** -0.25
    return xyz, speed, r, redrawn


def render_radius(r, a, n, k, c):
    """h = c (3 k m / (4 pi rho(r)))^(1/3) for M = 1, m = 1 / n."""
    return c * a * (k / n) ** (1.0 / 3.0) * (1.0 + (r / a) ** 2) ** (5.0 / 6.0)


def main(argv):
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--n", type=int, default=DEFAULT_N)
    parser.add_argument("--seed", type=int, default=DEFAULT_SEED)
    parser.add_argument("--a", type=float, default=DEFAULT_A,
                        help="Plummer scale length (default %(default)s)")
    parser.add_argument("--rmax", type=float, default=DEFAULT_RMAX_OVER_A,
                        help="truncation radius in scale lengths (default %(default)s)")
    parser.add_argument("--k", type=float, default=DEFAULT_K,
                        help="particles per sphere volume in the radius (default %(default)s)")
    parser.add_argument("--c", type=float, default=DEFAULT_C,
                        help="factor on the radius (default %(default)s)")
    parser.add_argument("output")
    args = parser.parse_args(argv[1:])
    n = args.n
    if n < 1:
        sys.exit("--n must be positive")
    if n > MAX_N:
        sys.exit(f"--n must be at most {MAX_N}: legacy VTK VERTICES hold 2 N int32 values")
    if not (args.a > 0 and args.rmax > 0 and args.k > 0 and args.c > 0):
        sys.exit("--a, --rmax, --k and --c must be positive")

    a = args.a
    rmax = args.rmax * a
    particle_mass = 1.0 / n
    rng = np.random.default_rng(args.seed)
    speed_all = np.empty(n, dtype=">f4")
    radius_all = np.empty(n, dtype=">f4")
    redrawn = 0
    inside_a = 0
    inside_rh = 0
    sum_v2 = 0.0
    r_h = expected_half_mass_radius(args.rmax) * a
    title = (f"Plummer sphere, {n} particles, G=M=1 N-body units, scale length a={a:g}, "
             f"truncated at {args.rmax:g} a, seed {args.seed}, numpy {np.__version__}")

    t0 = time.perf_counter()
    with open(args.output, "wb") as f:
        def text(s):
            f.write(s.encode("ascii"))

        # The same bytes as lammps_dump_to_vtk.write_vtk, one section at a time.
        text(f"# vtk DataFile Version 3.0\n{title[:255]}\nBINARY\nDATASET POLYDATA\n")
        text(f"POINTS {n} float\n")
        for start in range(0, n, CHUNK):
            m = min(CHUNK, n - start)
            xyz, speed, r, chunk_redrawn = sample_chunk(rng, m, a, rmax)
            f.write(xyz.astype(">f4").tobytes())
            speed_all[start:start + m] = speed
            radius_all[start:start + m] = render_radius(r, a, n, args.k, args.c)
            redrawn += chunk_redrawn
            inside_a += int(np.count_nonzero(r <= a))
            inside_rh += int(np.count_nonzero(r <= r_h))
            sum_v2 += float(np.dot(speed, speed))
            del xyz, speed, r
        t_sample = time.perf_counter() - t0

        text(f"\nVERTICES {n} {2 * n}\n")
        verts = np.empty((min(CHUNK, n), 2), dtype=">i4")
        verts[:, 0] = 1
        for start in range(0, n, CHUNK):
            m = min(CHUNK, n - start)
            verts[:m, 1] = np.arange(start, start + m)
            f.write(verts[:m].tobytes())
        del verts
        text(f"\nPOINT_DATA {n}\n")
        mass_chunk = np.full(min(CHUNK, n), particle_mass, dtype=">f4")
        for name, values in (("speed", speed_all), ("radius", radius_all), ("mass", None)):
            text(f"SCALARS {name} float 1\nLOOKUP_TABLE default\n")
            for start in range(0, n, CHUNK):
                m = min(CHUNK, n - start)
                f.write(mass_chunk[:m].tobytes() if values is None
                        else values[start:start + m].tobytes())
            text("\n")
    t_total = time.perf_counter() - t0

    # One summary line; plummer_sphere.sh copies it into the provenance file.
    x = args.rmax
    print(f"{n} particles (seed {args.seed}, numpy {np.__version__}), Plummer a={a:g} "
          f"(G=M=1) truncated at {x:g} a, particle mass {particle_mass:g}; {redrawn} radii "
          f"redrawn beyond {x:g} a; r <= a: {inside_a / n:.4f} "
          f"(Plummer: {mass_fraction(1.0) / mass_fraction(x):.4f}); r <= r_h = {r_h / a:.4f} a: "
          f"{inside_rh / n:.4f} (0.5); <v^2> {sum_v2 / n:.4f} (Plummer: "
          f"{expected_mean_v2(x) / a:.4f}); radius (k={args.k:g}, c={args.c:g}) min/median/max "
          f"{radius_all.min():.4g}/{np.median(radius_all):.4g}/{radius_all.max():.4g}; speed "
          f"max {speed_all.max():.4g}; times: sample {t_sample:.1f} s, total {t_total:.1f} s; "
          f"point arrays: speed radius mass")


if __name__ == "__main__":
    main(sys.argv)
