#include "Mappers/ZSweep/ZSweepNearPlane.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace raymappers
{

namespace
{
struct ClipVertex
{
  double c[4];
  double s;
  std::uint64_t key;
};

ClipVertex clipVertex(const std::array<double, 16>& M, const Vec3d& p, double s, std::uint64_t key)
{
  ClipVertex v;
  for (int k = 0; k < 4; ++k)
  {
    v.c[k] = M[4 * k] * p.x + M[4 * k + 1] * p.y + M[4 * k + 2] * p.z + M[4 * k + 3];
  }
  v.s = s;
  v.key = key;
  return v;
}

// Signed distance to the near plane in clip space (inside when >= 0).
double nearDistance(const ClipVertex& v)
{
  return v.c[2] + v.c[3];
}

// Where the edge (p, q) crosses the near plane, computed from the endpoint of smaller key.
ClipVertex crossing(const ClipVertex& p, const ClipVertex& q)
{
  const ClipVertex& a = p.key < q.key ? p : q;
  const ClipVertex& b = p.key < q.key ? q : p;
  const double da = nearDistance(a), db = nearDistance(b);
  const double t = da / (da - db);
  ClipVertex v;
  for (int k = 0; k < 4; ++k)
  {
    v.c[k] = a.c[k] + t * (b.c[k] - a.c[k]);
  }
  v.c[2] = -v.c[3]; // exactly on the plane
  v.s = a.s + t * (b.s - a.s);
  v.key = (static_cast<std::uint64_t>(a.key) + 1) << 32 | b.key;
  return v;
}

ProjectedVertex project(const ClipVertex& v, int width, int height)
{
  ProjectedVertex p;
  const double iw = v.c[3] > 0 ? 1.0 / v.c[3] : 0.0;
  p.x = (v.c[0] * iw + 1.0) * 0.5 * width;
  p.y = (v.c[1] * iw + 1.0) * 0.5 * height;
  p.d = std::max(0.0, (v.c[2] * iw + 1.0) * 0.5);
  p.invW = iw;
  p.valid = v.c[3] > 0;
  return p;
}

struct Segment
{
  ClipVertex a, b;
};

// Appends a triangle to draw, projected to the window, unless a corner is behind the eye.
void emitTriangle(const ClipVertex& a,
  const ClipVertex& b,
  const ClipVertex& c,
  std::int32_t entered,
  std::int32_t exited,
  int width,
  int height,
  std::vector<DrawTriangle>& out)
{
  DrawTriangle t;
  const ClipVertex* vs[3] = { &a, &b, &c };
  for (int k = 0; k < 3; ++k)
  {
    t.v[static_cast<std::size_t>(k)] = project(*vs[k], width, height);
    t.key[static_cast<std::size_t>(k)] = vs[k]->key;
    t.s[static_cast<std::size_t>(k)] = vs[k]->s;
  }
  t.entered = entered;
  t.exited = exited;
  if (t.v[0].valid && t.v[1].valid && t.v[2].valid)
  {
    out.push_back(t);
  }
}

// Sutherland-Hodgman of a triangle against z + w >= 0: the polygon of its part beyond the
// near plane, and `cut`, the points where its edges cross the plane (two when it crosses).
void clipAtNearPlane(const ClipVertex (&v)[3],
  std::vector<ClipVertex>& polygon,
  std::vector<ClipVertex>& cut)
{
  for (int k = 0; k < 3; ++k)
  {
    const ClipVertex& p = v[k];
    const ClipVertex& q = v[(k + 1) % 3];
    const bool pin = nearDistance(p) >= 0, qin = nearDistance(q) >= 0;
    if (pin)
    {
      polygon.push_back(p);
    }
    if (pin != qin)
    {
      polygon.push_back(crossing(p, q));
      cut.push_back(polygon.back());
    }
  }
}

// A cap's segments chained into a closed polygon (its cross-section with the near plane),
// by the keys of their ends; empty when they do not close (a degenerate cross-section).
std::vector<ClipVertex> closedRing(const std::vector<Segment>& segments)
{
  std::vector<ClipVertex> ring = { segments[0].a, segments[0].b };
  std::vector<char> used(segments.size(), 0);
  used[0] = 1;
  for (std::size_t step = 1; step < segments.size(); ++step)
  {
    const std::uint64_t tail = ring.back().key;
    bool found = false;
    for (std::size_t k = 0; k < segments.size() && !found; ++k)
    {
      if (used[k])
      {
        continue;
      }
      if (segments[k].a.key == tail || segments[k].b.key == tail)
      {
        used[k] = 1;
        found = true;
        ring.push_back(segments[k].a.key == tail ? segments[k].b : segments[k].a);
      }
    }
    if (!found)
    {
      break;
    }
  }
  if (ring.size() >= 4 && ring.back().key == ring.front().key)
  {
    ring.pop_back();
    return ring;
  }
  return {};
}
} // namespace

std::size_t nearPlaneTriangles(const ZSweepMesh& mesh,
  const std::vector<ZSweepTriangle>& triangles,
  const std::array<double, 16>& M,
  int width,
  int height,
  const std::vector<std::uint32_t>& crossingTriangles,
  const std::vector<char>& forward,
  std::vector<DrawTriangle>& out)
{
  const auto& points = mesh.points();
  const auto& scalars = mesh.scalars();
  const bool cellData = mesh.cellScalars();
  std::map<std::int32_t, std::vector<Segment>> caps; // cell -> its crossing segments

  // The faces: the fan of each clipped part, the rays crossing it as they cross the face;
  // the segment where it crosses the plane goes to the caps of the cells on its sides.
  for (const std::uint32_t f : crossingTriangles)
  {
    const ZSweepTriangle& tri = triangles[f];
    ClipVertex v[3];
    for (int k = 0; k < 3; ++k)
    {
      const std::uint32_t id = tri.v[k];
      v[k] = clipVertex(M, points[id], cellData ? 0.0 : scalars[id], id);
    }
    std::vector<ClipVertex> polygon;
    std::vector<ClipVertex> cut;
    clipAtNearPlane(v, polygon, cut);
    const std::int32_t entered = forward[f] ? tri.back : tri.front;
    const std::int32_t exited = forward[f] ? tri.front : tri.back;
    for (std::size_t k = 1; k + 1 < polygon.size(); ++k)
    {
      emitTriangle(polygon[0], polygon[k], polygon[k + 1], entered, exited, width, height, out);
    }
    if (cut.size() == 2)
    {
      for (const std::int32_t cell : { tri.front, tri.back })
      {
        if (cell >= 0)
        {
          caps[cell].push_back({ cut[0], cut[1] });
        }
      }
    }
  }

  // The caps: each closed cross-section as a fan, the ray entering its cell there.
  std::size_t open = 0;
  for (const auto& [cell, segments] : caps)
  {
    const std::vector<ClipVertex> ring = closedRing(segments);
    if (ring.empty())
    {
      ++open;
      continue;
    }
    for (std::size_t k = 1; k + 1 < ring.size(); ++k)
    {
      emitTriangle(ring[0], ring[k], ring[k + 1], cell, -1, width, height, out);
    }
  }
  return open;
}

} // namespace raymappers
