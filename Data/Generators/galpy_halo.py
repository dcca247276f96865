#!/usr/bin/python3
"""Sample the particles of a dark-matter halo from galpy's self-consistent
distribution function and write them as legacy VTK binary polydata.

Usage: galpy_halo.py [--n N] [--seed S] [--scale-radius KPC] [--rmax A]
                     [--mass MSUN] [--k K] [--radius-method knn|analytic]
                     OUTPUT.vtk

The halo: an NFW profile, rho(r) = M0 / (4 pi a^3) / ((r/a) (1 + r/a)^2),
with scale radius a = 16 kpc (as in galpy's MWPotential2014) and mass
1e12 Msun inside rmax = 20 a = 320 kpc, i.e. a Milky-Way-like halo of
concentration rmax / a = 20. Particles are drawn with galpy's isotropicNFWdf (the
isotropic Eddington distribution function of the NFW potential, Lane et al.
2021 fit) and its .sample(n=N), which draws r from the mass profile, the
angles uniformly and |v| from f(E) at that radius.

Far outliers: the NFW mass diverges logarithmically, so an untruncated
sample has no natural edge (with galpy's default cut-off rmax = 1e4 a,
75 % of the particles would lie beyond 20 a). The DF is therefore truncated
at rmax = 20 a with galpy's own rmax= argument: radii are drawn from the NFW
mass profile inside rmax, and f(E) = 0 for E > Phi(rmax), so every particle
is bound inside rmax. Any particle that spline round-off in the sampler
still puts beyond rmax is redrawn (the count is printed; none at the
defaults), so the file has exactly N particles.

Output, in kpc, km/s and Msun: float points (the halo centre is the origin),
one VERTEX cell per particle (as lammps_dump_to_vtk.py writes), and the
float point arrays, in this order:
  speed   |v| (km/s); the active scalars, so a plain reader colours by it
  smoothing_length  h (kpc): the distance to the k-th nearest other
          particle, k = 32, from scipy.spatial.cKDTree (--radius-method knn,
          the default; galpy depends on scipy, so it is always there with
          Debian's package). --radius-method analytic (and the fallback when
          scipy cannot be imported) uses the radius of the sphere that holds
          k particles' mass at the profile's local density instead:
          h = (3 k m / (4 pi rho(r)))^(1/3), a smooth function of r.
  mass    every particle's mass, 1e12 Msun / N (equal masses)
Points are in sampling order (random). The random seed is fixed (--seed,
default 1): galpy draws from numpy's global generator, which is seeded.
Legacy .vtk is used because Debian 12's VTK fails on XML files with
appended data (see SETUP.md). Run with Debian's /usr/bin/python3.
"""

import argparse
import os
import sys
import time

import numpy as np

# The legacy-VTK polydata writer shared with the LAMMPS converter (same folder).
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lammps_dump_to_vtk import write_vtk  # noqa: E402

DEFAULT_N = 1_000_000
DEFAULT_SEED = 1
DEFAULT_SCALE_RADIUS_KPC = 16.0
DEFAULT_RMAX_OVER_A = 20.0
DEFAULT_MASS_MSUN = 1.0e12
DEFAULT_K = 32
# galpy's natural units (its defaults): lengths in ro kpc, velocities in vo km/s.
RO_KPC = 8.0
VO_KMS = 220.0


def make_df(scale_radius_kpc, rmax_over_a, mass_msun):
    """The NFW potential and its isotropic DF truncated at rmax, in galpy's natural units."""
    from galpy.df import isotropicNFWdf
    from galpy.potential import NFWPotential, mass
    from galpy.util import conversion

    a = scale_radius_kpc / RO_KPC
    rmax = rmax_over_a * a
    # amp is M0 of M(<r) = M0 (ln(1 + r/a) - (r/a)/(1 + r/a)); scale it so
    # that the mass inside rmax is mass_msun.
    unit_pot = NFWPotential(amp=1.0, a=a)
    m_unit = mass(unit_pot, rmax, use_physical=False)
    amp = mass_msun / conversion.mass_in_msol(VO_KMS, RO_KPC) / m_unit
    pot = NFWPotential(amp=amp, a=a)
    df = isotropicNFWdf(pot=pot, rmax=rmax)
    return pot, df, rmax


def sample(df, n, rmax):
    """n particles as (xyz, vxyz) in natural units, all with r <= rmax."""
    xyz = np.empty((n, 3))
    vxyz = np.empty((n, 3))
    filled = 0
    redrawn = 0
    while filled < n:
        orbits = df.sample(n=n - filled)
        pos = np.column_stack([orbits.x(use_physical=False), orbits.y(use_physical=False),
                               orbits.z(use_physical=False)])
        vel = np.column_stack([orbits.vx(use_physical=False), orbits.vy(use_physical=False),
                               orbits.vz(use_physical=False)])
        keep = np.einsum("ij,ij->i", pos, pos) <= rmax * rmax
        keep &= np.all(np.isfinite(pos), axis=1) & np.all(np.isfinite(vel), axis=1)
        m = int(keep.sum())
        xyz[filled:filled + m] = pos[keep]
        vxyz[filled:filled + m] = vel[keep]
        filled += m
        redrawn += len(keep) - m
    return xyz, vxyz, redrawn


def knn_radius(xyz, k):
    """Distance to the k-th nearest other point (the point itself is excluded)."""
    from scipy.spatial import cKDTree
    tree = cKDTree(xyz)
    # k + 1: the nearest "neighbour" of a point is itself, at distance 0.
    dist, _ = tree.query(xyz, k=[k + 1])
    return dist[:, 0]


def analytic_radius(pot, xyz_natural, k, particle_mass_natural):
    """Radius of the sphere holding k particles' mass at the profile's density."""
    r_cyl = np.hypot(xyz_natural[:, 0], xyz_natural[:, 1])
    rho = pot.dens(r_cyl, xyz_natural[:, 2], use_physical=False)
    return (3.0 * k * particle_mass_natural / (4.0 * np.pi * rho)) ** (1.0 / 3.0)


def main(argv):
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--n", type=int, default=DEFAULT_N)
    parser.add_argument("--seed", type=int, default=DEFAULT_SEED)
    parser.add_argument("--scale-radius", type=float, default=DEFAULT_SCALE_RADIUS_KPC,
                        help="NFW scale radius a in kpc (default %(default)s)")
    parser.add_argument("--rmax", type=float, default=DEFAULT_RMAX_OVER_A,
                        help="truncation radius in scale radii (default %(default)s)")
    parser.add_argument("--mass", type=float, default=DEFAULT_MASS_MSUN,
                        help="mass inside rmax in Msun (default %(default)g)")
    parser.add_argument("--k", type=int, default=DEFAULT_K)
    parser.add_argument("--radius-method", choices=("knn", "analytic"), default="knn")
    parser.add_argument("output")
    args = parser.parse_args(argv[1:])
    if args.n < args.k + 1:
        sys.exit(f"--n must be at least k + 1 = {args.k + 1}")

    import galpy

    np.random.seed(args.seed)  # galpy samples with numpy's global generator
    t0 = time.perf_counter()
    pot, df, rmax = make_df(args.scale_radius, args.rmax, args.mass)
    xyz_nat, vxyz_nat, redrawn = sample(df, args.n, rmax)
    t_sample = time.perf_counter() - t0

    xyz = xyz_nat * RO_KPC
    speed = np.linalg.norm(vxyz_nat, axis=1) * VO_KMS
    particle_mass = args.mass / args.n

    t1 = time.perf_counter()
    method = args.radius_method
    if method == "knn":
        try:
            radius = knn_radius(xyz.astype(np.float32).astype(np.float64), args.k)
        except ImportError:
            method = "analytic (scipy missing)"
    if method != "knn":
        from galpy.util import conversion
        m_nat = particle_mass / conversion.mass_in_msol(VO_KMS, RO_KPC)
        radius = analytic_radius(pot, xyz_nat, args.k, m_nat) * RO_KPC
    t_radius = time.perf_counter() - t1

    n = args.n
    a_kpc = args.scale_radius
    title = (f"galpy {galpy.__version__} isotropic NFW halo, {n} particles, a={a_kpc:g} kpc, "
             f"truncated at {args.rmax:g} a, M={args.mass:g} Msun, seed {args.seed}, "
             f"kpc km/s Msun")
    t2 = time.perf_counter()
    write_vtk(args.output, xyz.astype(np.float32),
              [(name, values, "float", ">f4") for name, values in
               (("speed", speed), ("smoothing_length", radius), ("mass", np.full(n, particle_mass)))],
              title)
    t_write = time.perf_counter() - t2

    # One summary line; galpy_halo.sh copies it into the provenance file.
    r = np.linalg.norm(xyz, axis=1)
    inside_a = np.mean(r <= a_kpc)
    x = args.rmax
    expected_inside_a = (np.log(2.0) - 0.5) / (np.log1p(x) - x / (1.0 + x))
    print(f"{n} particles (seed {args.seed}, galpy {galpy.__version__}), NFW a={a_kpc:g} kpc "
          f"truncated at {args.rmax:g} a = {args.rmax * a_kpc:g} kpc, particle mass "
          f"{particle_mass:g} Msun; {redrawn} redrawn beyond rmax; r <= a: {inside_a:.4f} "
          f"(NFW: {expected_inside_a:.4f}); smoothing_length ({method}, k={args.k}) min/median/max "
          f"{radius.min():.4g}/{np.median(radius):.4g}/{radius.max():.4g} kpc; speed max "
          f"{speed.max():.4g} km/s; times: sample {t_sample:.1f} s, radius {t_radius:.1f} s, "
          f"write {t_write:.1f} s; point arrays: speed smoothing_length mass")


if __name__ == "__main__":
    main(sys.argv)
