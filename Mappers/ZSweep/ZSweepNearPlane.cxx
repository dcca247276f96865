#include "ZSweepNearPlane.h"

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

  auto emit = [&](const ClipVertex& a, const ClipVertex& b, const ClipVertex& c,
                std::int32_t entered, std::int32_t exited) {
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
  };

  for (const std::uint32_t f : crossingTriangles)
  {
    const ZSweepTriangle& tri = triangles[f];
    ClipVertex v[3];
    for (int k = 0; k < 3; ++k)
    {
      const std::uint32_t id = tri.v[k];
      v[k] = clipVertex(M, points[id], cellData ? 0.0 : scalars[id], id);
    }
    // Sutherland-Hodgman against z + w >= 0: the part beyond the near plane, and the
    // segment where the face crosses it.
    std::vector<ClipVertex> polygon;
    std::vector<ClipVertex> cut;
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
    const std::int32_t entered = forward[f] ? tri.back : tri.front;
    const std::int32_t exited = forward[f] ? tri.front : tri.back;
    for (std::size_t k = 1; k + 1 < polygon.size(); ++k)
    {
      emit(polygon[0], polygon[k], polygon[k + 1], entered, exited);
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

  // Each cap: chain its segments into a closed polygon, then a fan entering the cell.
  std::size_t open = 0;
  for (auto& [cell, segments] : caps)
  {
    std::vector<ClipVertex> ring = { segments[0].a, segments[0].b };
    std::vector<char> used(segments.size(), 0);
    used[0] = 1;
    bool closed = false;
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
      closed = true;
    }
    if (!closed)
    {
      ++open;
      continue;
    }
    for (std::size_t k = 1; k + 1 < ring.size(); ++k)
    {
      emit(ring[0], ring[k], ring[k + 1], cell, -1);
    }
  }
  return open;
}

} // namespace raymappers
