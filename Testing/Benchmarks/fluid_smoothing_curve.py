"""The fluid's smoothing radius against the union of its spheres: the measured curve behind
vtkSPHFluidMapper's default SmoothingRadius.

For each SmoothingRadius R (in particle radii, LengthUnit PARTICLE_RADIUS) the particles are
voxelized by vtkSPHVoxelizer (the mapper's kernels) for one camera, and per pixel the front
surface is compared with the union of the spheres, intersected here ray by ray in double
(numpy, no code of the mapper):
  error   |front distance - the union's| / r along the ray on the pixels both cover: the
          99th percentile and the largest (the largest is at grazing silhouettes, where a
          pixel's step in depth is long and the filter, one-sided at the edge, pulls the
          depth towards the interior's);
  offset  the distance of the smoothed front point to the union's surface, | min_i |p - c_i|
          - r | / r (exact outside the union, for one radius): how far the surface moved
          in space, whatever the angle it is seen at; 99th percentile and largest;
  bumps   the particle-lattice bumps: the RMS angle between the surface normal and the
          normal averaged over a Gaussian of one particle spacing (normalized convolution on
          the covered pixels, pixels nearer than 2 sigma to an edge left out); for the union
          of spheres itself too (its analytic normals): the bumps the data has. For the
          lattice, whose smooth shape is a box, the RMS angle to the normal of the box's
          face nearest to the point instead (points within 2 radii of a second face, at
          the box's edges, left out).
  filter_ms the smoothing phase's time (the voxelizer's statistics).
Prints one CSV row per R.

usage: pvpython fluid_smoothing_curve.py BUILD_DIR DATA.vtk [--size WxH] [--radii 0,0.5,1]
       [--iterations N]
"""
import argparse
import math
import os
import sys

import numpy as np
from scipy import ndimage
from scipy.spatial import cKDTree

parser = argparse.ArgumentParser()
parser.add_argument("build")
parser.add_argument("data", help="a legacy .vtk particle file, or 'lattice': PySPH's initial "
                    "dam (a cubic lattice of spacing 0.04, 30 x 15 x 12 particles)")
parser.add_argument("--size", default="640x480")
parser.add_argument("--radii", default="0,0.25,0.5,0.75,1,1.5,2,3,4")
parser.add_argument("--iterations", type=int, default=20, help="SmoothingIterations")
parser.add_argument("--position", default="0.0,-3.4,1.9")
parser.add_argument("--focal", default="0.9,0.0,0.2")
args = parser.parse_args()
sys.path.insert(0, os.path.join(args.build, "lib", "python3", "dist-packages"))

from vtkmodules.vtkIOLegacy import vtkPolyDataReader  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
import raymappers  # noqa: E402

W, H = (int(v) for v in args.size.split("x"))
if args.data == "lattice":
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkPolyData
    from vtkmodules.util.numpy_support import numpy_to_vtk
    g = np.mgrid[0:30, 0:15, 0:12].reshape(3, -1).T * 0.04 + [0.3, -0.3, 0.04]
    points = vtkPoints()
    points.SetData(numpy_to_vtk(g, deep=True))
    particles = vtkPolyData()
    particles.SetPoints(points)
else:
    reader = vtkPolyDataReader()
    reader.SetFileName(args.data)
    reader.Update()
    particles = reader.GetOutput()
centres = vtk_to_numpy(particles.GetPoints().GetData()).astype(float)


def voxelize(radius):
    vox = raymappers.vtkSPHVoxelizer()
    vox.SetInputData(particles)
    vox.SetImageSize(W, H)
    vox.SetCameraPosition(*(float(v) for v in args.position.split(",")))
    vox.SetCameraFocalPoint(*(float(v) for v in args.focal.split(",")))
    vox.SetCameraViewUp(0, 0, 1)
    vox.SetCameraViewAngle(30)
    vox.ResetCameraOff()
    vox.SetSmoothingRadius(radius)
    vox.SetSmoothingIterations(args.iterations)
    vox.Update()
    return vox


def pointArray(image, name):
    return vtk_to_numpy(image.GetPointData().GetArray(name)).reshape(H, W, -1)


def rays(image):
    """Pixel centre rays: eye and unit directions from the inverse of the matrix used."""
    m = vtk_to_numpy(image.GetFieldData().GetArray("ModelToClip")).reshape(4, 4)
    inv = np.linalg.inv(m)
    x = (np.arange(W) + 0.5) / W * 2 - 1
    y = (np.arange(H) + 0.5) / H * 2 - 1
    X, Y = np.meshgrid(x, y)
    ends = []
    for z in (-1.0, 1.0):
        ndc = np.stack([X, Y, np.full_like(X, z), np.ones_like(X)], axis=-1)
        w = ndc @ inv.T
        ends.append(w[..., :3] / w[..., 3:4])
    d = ends[1] - ends[0]
    return ends[0], d / np.linalg.norm(d, axis=-1, keepdims=True)


def unionFront(eye, direction, radius, m):
    """Distance from `eye` to the first sphere along each ray (inf: none) and its normal."""
    best = np.full((H, W), np.inf)
    normal = np.zeros((H, W, 3))
    for c in centres:
        clip = m @ np.append(c, 1.0)
        if clip[3] <= 0:
            continue
        px, py = (clip[0] / clip[3] + 1) * 0.5 * W, (clip[1] / clip[3] + 1) * 0.5 * H
        reach = radius / (clip[3] * 0.5 * math.tan(math.radians(15)) * 2) * H + 2
        i0, i1 = max(0, int(px - reach)), min(W, int(px + reach) + 1)
        j0, j1 = max(0, int(py - reach)), min(H, int(py + reach) + 1)
        if i0 >= i1 or j0 >= j1:
            continue
        D = direction[j0:j1, i0:i1]
        A = eye - c
        b = D @ A
        disc = b * b - (A @ A - radius * radius)
        hit = disc > 0
        t = np.where(hit, -b - np.sqrt(np.where(hit, disc, 0)), np.inf)
        sub = best[j0:j1, i0:i1]
        closer = t < sub
        sub[closer] = t[closer]
        p = eye + D * t[..., None]
        n = (p - c) / radius
        normal[j0:j1, i0:i1][closer] = n[closer]
    return best, normal


def bumps(normal, mask, sigma):
    """RMS angle (degrees) between the normal and its Gaussian average of width sigma px."""
    normal = np.where(mask[..., None], np.nan_to_num(normal), 0.0)
    weights = ndimage.gaussian_filter(mask.astype(float), sigma)
    mean = np.stack([ndimage.gaussian_filter(normal[..., k] * mask, sigma) for k in range(3)],
                    axis=-1) / np.maximum(weights, 1e-12)[..., None]
    mean /= np.maximum(np.linalg.norm(mean, axis=-1, keepdims=True), 1e-12)
    inner = ndimage.binary_erosion(mask, iterations=int(math.ceil(2 * sigma)))
    inner &= np.all(np.isfinite(normal), axis=-1) & np.all(np.isfinite(mean), axis=-1)
    cosines = np.clip(np.sum(normal * mean, axis=-1), -1, 1)[inner]
    return math.degrees(math.sqrt(np.mean(np.arccos(cosines) ** 2))), int(inner.sum())


def boxBumps(points, normal, rayDirection):
    """RMS angle (degrees) to the nearest face's normal of the lattice's box, off its edges,
    on the faces seen at less than 60 degrees from their normal (a grazing face's pixels are
    several radii long: its bumps are below a pixel)."""
    lo, hi = centres.min(axis=0) - radius, centres.max(axis=0) + radius
    gaps = np.concatenate([points - lo, hi - points], axis=1)  # distance to the 6 faces
    order = np.argsort(gaps, axis=1)
    second = np.take_along_axis(gaps, order[:, 1:2], axis=1)[:, 0]
    face = order[:, 0]
    axisNormal = np.zeros((len(face), 3))
    axisNormal[np.arange(len(face)), face % 3] = np.where(face < 3, -1.0, 1.0)
    facing = -np.sum(axisNormal * rayDirection, axis=1) > 0.5
    keep = (second > 2 * radius) & np.all(np.isfinite(normal), axis=1) & facing
    axisNormal = axisNormal[keep]
    cosines = np.clip(np.sum(normal[keep] * axisNormal, axis=1), -1, 1)
    return math.degrees(math.sqrt(np.mean(np.arccos(cosines) ** 2))), int(keep.sum())


plain = voxelize(0.0)
radius = plain.GetRadiusInUse(particles)
image0 = plain.GetOutput()
m = vtk_to_numpy(image0.GetFieldData().GetArray("ModelToClip")).reshape(4, 4)
eye = np.array([float(v) for v in args.position.split(",")])
_, direction = rays(image0)
ref, refNormal = unionFront(eye, direction, radius, m)
covered = np.isfinite(ref)
# One particle spacing (2 r) in pixels at the median depth of the fluid.
depth = np.median(ref[covered])
pixel = 2 * depth * math.tan(math.radians(15)) / H
sigma = 2 * radius / pixel
refPoints = eye + direction[covered] * ref[covered][:, None]
refBumps, _ = boxBumps(refPoints, refNormal[covered], direction[covered]) \
    if args.data == "lattice" else \
    bumps(refNormal, covered, sigma)
print(f"# {len(centres)} particles, radius {radius:.5g}, {W}x{H}, spacing {sigma:.1f} px, "
      f"union-of-spheres bumps {refBumps:.2f} deg")
tree = cKDTree(centres)
print("smoothing_radius_r,iterations,error_p99_r,error_max_r,offset_p99_r,offset_max_r,"
      "pixels_error_over_1r,bumps_deg,bump_pixels,filter_ms")
for R in (float(v) for v in args.radii.split(",")):
    vox = voxelize(R)
    image = vox.GetOutput()
    count = pointArray(image, "SpanCount")[..., 0]
    entry = pointArray(image, "EntryDepth")[..., 0] * pointArray(image, "DepthToDistance")[..., 0]
    normal = pointArray(image, "EntryNormal")[..., :3].astype(float)
    both = covered & (count > 0)
    err = np.abs(entry - ref)[both] / radius
    points = eye + direction[both] * entry[both][:, None]
    offset = np.abs(tree.query(points)[0] - radius) / radius
    b, n = boxBumps(points, normal[both], direction[both]) if args.data == "lattice" else \
        bumps(normal, count > 0, sigma)
    summary = vox.GetStatisticsSummary()
    iterations = next((line.split()[-1] for line in summary.splitlines()
                       if line.startswith("counter filter_iterations")), "0")
    filterMs = next((float(line.split()[-1]) for line in summary.splitlines()
                     if line.startswith("phase filter")), 0.0)
    print(f"{R:g},{iterations},{np.percentile(err, 99):.3f},{err.max():.3f},"
          f"{np.percentile(offset, 99):.3f},{offset.max():.3f},{int((err > 1).sum())},{b:.2f},{n},"
          f"{filterMs:.1f}")
