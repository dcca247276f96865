// Ray packets as the accelerators receive them: lanes outside the image or the pixel block
// (valid false) hold whatever the memory held, and a lane marked valid may carry a ray no
// accelerator can trace (a NaN direction from a degenerate shadow ray, an origin at
// infinity, an interval behind the origin). Embree 3.13 traces a 16-ray packet on CPUs
// without AVX-512 through its ray-stream code, which ignores the valid mask and traces
// every lane with tnear <= tfar; its assertions (on in Debian's build) abort on such a lane
// that is not a valid ray. Embree's code path is chosen here through its device
// configuration, so each path runs on any CPU that has its instructions (and is skipped on
// one that has not).
#include "CameraFixtures.h"
#include "Mappers/CGT/CoherentGridAccelerator.h"
#include "Mappers/CGT/EmbreeSphereAccelerator.h"
#include "SphereReference.h"
#include "Mappers/CGT/SphereRenderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

using namespace raymappers;
using namespace raymappers::test;

namespace
{
const float nan32 = std::numeric_limits<float>::quiet_NaN();
const float inf32 = std::numeric_limits<float>::infinity();

// What Embree's RayK::valid() and its tnear assertion accept (kernels/common/ray.h):
// origin and direction components within FLT_LARGE (1.844e18), tnear in [0, inf], tfar
// not NaN.
bool embreeAccepts(const RTCRayHit16& rh, int k)
{
  const float large = 1.844e18f;
  for (const float x : { rh.ray.org_x[k],
         rh.ray.org_y[k],
         rh.ray.org_z[k],
         rh.ray.dir_x[k],
         rh.ray.dir_y[k],
         rh.ray.dir_z[k] })
  {
    if (!(std::fabs(x) <= large))
    {
      return false;
    }
  }
  return rh.ray.tnear[k] >= 0.f && std::fabs(rh.ray.tnear[k]) <= inf32 &&
         std::fabs(rh.ray.tfar[k]) <= inf32;
}

// A lane that Embree's stream code skips whatever the valid mask says: tnear > tfar.
bool streamSkips(const RTCRayHit16& rh, int k)
{
  return rh.ray.tnear[k] > rh.ray.tfar[k];
}

// Memory contents a lane may hold: every byte 0xFF (NaN floats), ASan's fill byte 0xBE
// (-0.37: a negative tnear), and rays the stream code would trace (tnear <= tfar) from
// origins at 1e30.
void poison(RTCRayHit16& rh, int pattern)
{
  if (pattern < 2)
  {
    std::memset(&rh, pattern == 0 ? 0xFF : 0xBE, sizeof rh);
    return;
  }
  float* f = reinterpret_cast<float*>(&rh);
  for (std::size_t i = 0; i < sizeof rh / sizeof(float); ++i)
  {
    f[i] = 1e30f;
  }
}

Ray garbageRay(int k)
{
  Ray r;
  r.org = Vec3f(k % 2 ? nan32 : 1e30f, 0.f, 0.f);
  r.dir = Vec3f(nan32, nan32, nan32);
  r.tnear = k % 3 ? -1.f : 0.f;
  r.tfar = 1e30f;
  return r;
}

Ray goodRay(int k)
{
  Ray r;
  r.org = Vec3f(0.1f * k, -0.2f * k, 3.f);
  r.dir = Vec3f(0.f, 0.f, -1.f);
  r.tnear = 0.f;
  r.tfar = 10.f + k;
  return r;
}

// A packet of side x side lanes: lanes with k % 3 == 1 are not valid and hold garbage.
RayPacket mixedPacket(int side)
{
  RayPacket packet;
  packet.side = side;
  for (int k = 0; k < MaxPacketRays; ++k)
  {
    packet.valid[k] = k % 3 != 1;
    packet.rays[k] = packet.valid[k] ? goodRay(k) : garbageRay(k);
  }
  return packet;
}
}

TEST(EmbreePacket, InactiveLanesAreEmptyRaysWhateverTheMemoryHeld)
{
  for (const int side : { 3, 4, 5, 8 })
  {
    const RayPacket packet = mixedPacket(side);
    const int n = side * side;
    for (int pattern = 0; pattern < 3; ++pattern)
    {
      for (int base = 0; base < n; base += 16)
      {
        alignas(64) RTCRayHit16 rh;
        alignas(64) int valid[16];
        poison(rh, pattern);
        EXPECT_TRUE(EmbreeSphereAccelerator::toEmbreePacket(packet, base, rh, valid));
        for (int k = 0; k < 16; ++k)
        {
          const int lane = base + k;
          const std::string where = "side " + std::to_string(side) + " pattern " +
                                    std::to_string(pattern) + " lane " + std::to_string(lane);
          const bool traced = lane < n && packet.valid[lane];
          ASSERT_EQ(valid[k], traced ? -1 : 0) << where;
          EXPECT_TRUE(embreeAccepts(rh, k)) << where;
          if (traced)
          {
            const Ray& r = packet.rays[lane];
            EXPECT_EQ(rh.ray.org_x[k], r.org.x) << where;
            EXPECT_EQ(rh.ray.dir_z[k], r.dir.z) << where;
            EXPECT_EQ(rh.ray.tnear[k], r.tnear) << where;
            EXPECT_EQ(rh.ray.tfar[k], r.tfar) << where;
            EXPECT_EQ(rh.hit.geomID[k], RTC_INVALID_GEOMETRY_ID) << where;
          }
          else
          {
            EXPECT_TRUE(streamSkips(rh, k)) << where;
          }
        }
      }
    }
  }
}

TEST(EmbreePacket, ValidLanesEmbreeCannotTraceAreLeftOut)
{
  // Lanes marked valid whose rays Embree rejects: left out of the trace (a miss) and made
  // empty like the lanes outside the image.
  RayPacket packet;
  packet.side = 4;
  for (int k = 0; k < 16; ++k)
  {
    packet.valid[k] = true;
    packet.rays[k] = goodRay(k);
  }
  packet.rays[1].dir = Vec3f(nan32, 0.f, 0.f); // a shadow ray towards its own start: 0 / 0
  packet.rays[2].org = Vec3f(inf32, 0.f, 0.f);
  packet.rays[3].org = Vec3f(0.f, 2e18f, 0.f);
  packet.rays[4].tnear = -0.5f;
  packet.rays[5].tnear = nan32;
  packet.rays[6].tfar = nan32;
  packet.rays[7].tnear = 20.f; // past tfar: an empty interval
  alignas(64) RTCRayHit16 rh;
  alignas(64) int valid[16];
  poison(rh, 2);
  EXPECT_TRUE(EmbreeSphereAccelerator::toEmbreePacket(packet, 0, rh, valid));
  for (int k = 0; k < 16; ++k)
  {
    const bool bad = k >= 1 && k <= 7;
    EXPECT_EQ(valid[k], bad ? 0 : -1) << "lane " << k;
    EXPECT_TRUE(embreeAccepts(rh, k)) << "lane " << k;
    EXPECT_EQ(streamSkips(rh, k), bad) << "lane " << k;
  }
  // A packet with nothing to trace says so.
  for (int k = 0; k < 16; ++k)
  {
    packet.valid[k] = k >= 1 && k <= 7;
  }
  EXPECT_FALSE(EmbreeSphereAccelerator::toEmbreePacket(packet, 0, rh, valid));
}

namespace
{
SphereSet randomSpheres(int n, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> pos(-3, 3), rad(0.2, 0.6);
  std::vector<Vec3d> p(static_cast<std::size_t>(n));
  std::vector<double> r(p.size());
  for (std::size_t i = 0; i < p.size(); ++i)
  {
    p[i] = { pos(rng), pos(rng), pos(rng) };
    r[i] = rad(rng);
  }
  SphereSet s;
  buildSphereSet(
    p.size(),
    Vec3d(0.2, 0.1, -0.3),
    [&](std::size_t i) { return p[i]; },
    [&](std::size_t i) { return r[i]; },
    [](std::size_t i) { return packRGBA8(i % 256, 128, 64, 255); },
    s);
  return s;
}

RayCamera viewOf(const SphereSet& s, const Vec3d& eye, int w, int h)
{
  const Mat4 m = multiply(perspective(40, double(w) / h, 0.5, 200), lookAt(eye, {}, { 0, 1, 0 }));
  return RayCamera(m, w, h, s.origin);
}

// Leaves the stack below the caller full of 1e30: rays that Embree's stream code would
// trace and whose origins its assertions reject. Whatever the next call at this depth
// leaves uninitialised in its frame then holds such garbage rather than a fresh stack's
// zeros, as it may after any earlier work of the thread.
__attribute__((noinline)) void poisonStack()
{
  float junk[8192];
  std::fill(std::begin(junk), std::end(junk), 1e30f);
  // The stores are the point: the compiler must not drop them.
  __asm__ volatile("" : : "r"(junk) : "memory");
}

// The accelerators: the coherent grid, and Embree on each of its x86 code paths, chosen by
// its device configuration. A path the CPU lacks is skipped.
struct Accelerator
{
  const char* name;
  const char* embreeConfig; // nullptr: the coherent grid
  bool (*cpuHasIt)();
};

const Accelerator Accelerators[] = {
  { "grid", nullptr, [] { return true; } },
  { "embree_avx512",
    "isa=avx512",
    []
    {
      return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") &&
             __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw") &&
             __builtin_cpu_supports("avx512vl");
    } },
  { "embree_avx2", "isa=avx2", [] { return __builtin_cpu_supports("avx2") != 0; } },
  { "embree_sse42", "isa=sse4.2", [] { return __builtin_cpu_supports("sse4.2") != 0; } },
};

std::unique_ptr<SphereAccelerator> makeAccelerator(const Accelerator& which, SphereSet& s)
{
  if (!which.embreeConfig)
  {
    auto grid = std::make_unique<CoherentGridAccelerator>();
    grid->build(s, CoherentGridParameters{});
    return grid;
  }
  auto bvh = std::make_unique<EmbreeSphereAccelerator>(which.embreeConfig);
  bvh->build(s);
  return bvh;
}

class EveryAccelerator : public testing::TestWithParam<Accelerator>
{
protected:
  void SetUp() override
  {
    if (!GetParam().cpuHasIt())
    {
      GTEST_SKIP() << "this CPU cannot run " << GetParam().name;
    }
  }
};

// Embree's code paths alone.
class EveryEmbreeIsa : public EveryAccelerator
{
};

std::string nameOf(const testing::TestParamInfo<Accelerator>& info)
{
  return info.param.name;
}
}

TEST_P(EveryAccelerator, LanesOutsideThePacketAndUntraceableRaysMiss)
{
  // Primary rays of a camera in packets of 4 x 4 and 8 x 8 lanes, a third of the lanes not
  // valid (garbage rays; in the 8 x 8 packets all of lanes 16 to 31), two valid lanes with
  // rays no accelerator can trace. The good lanes get the brute-force hit, every other lane
  // no hit.
  SphereSet s = randomSpheres(200, 5);
  const RayCamera cam = viewOf(s, { 2, 3, 12 }, 64, 64);
  const std::unique_ptr<SphereAccelerator> accel = makeAccelerator(GetParam(), s);
  int checked = 0, hits = 0;
  for (const int side : { 4, 8 })
  {
    for (int by = 0; by + side <= cam.height(); by += side)
    {
      for (int bx = 0; bx + side <= cam.width(); bx += side)
      {
        RayPacket packet = mixedPacket(side);
        for (int k = 0; k < side * side; ++k)
        {
          if (packet.valid[k])
          {
            packet.rays[k] = cam.pixelRay(bx + k % side, by + k / side);
          }
        }
        if (side == 8)
        {
          // the second 16 lanes all outside: Embree has nothing to trace there
          std::fill(packet.valid + 16, packet.valid + 32, false);
        }
        packet.rays[0].dir = Vec3f(nan32, nan32, nan32);
        packet.rays[side * side - 1].tnear = -1.f;
        PacketHits result;
        std::fill(std::begin(result.prim), std::end(result.prim), 12345u);
        TraversalCounters counters;
        poisonStack();
        accel->intersect(packet, result, counters);
        for (int k = 0; k < side * side; ++k)
        {
          const std::string where = "side " + std::to_string(side) + " pixel " +
                                    std::to_string(bx + k % side) + "," +
                                    std::to_string(by + k / side);
          if (!packet.valid[k] || k == 0 || k == side * side - 1)
          {
            EXPECT_EQ(result.prim[k], NoHit) << where;
            continue;
          }
          double t, margin;
          const int id = bruteForce(s, packet.rays[k], t, margin);
          if (margin < 1e-4)
          {
            continue; // grazing: float and double may disagree
          }
          ++checked;
          hits += id >= 0;
          ASSERT_EQ(result.prim[k], id < 0 ? NoHit : static_cast<std::uint32_t>(id)) << where;
          if (id >= 0)
          {
            EXPECT_NEAR(result.t[k], t, 1e-4 * t) << where;
          }
        }
      }
    }
  }
  EXPECT_GT(checked, 2 * 64 * 64 / 2);
  EXPECT_GT(hits, checked / 4);
}

TEST_P(EveryEmbreeIsa, RendersTheGridsImage)
{
  // The renderer's own packets: an image width that leaves lanes past the tile edge, shadow
  // rays (3 x 3 of a 4 x 4 packet) and ambient occlusion rays (10 of 16). Each of Embree's
  // code paths gives the coherent grid's image.
  SphereSet s = randomSpheres(300, 9);
  const RayCamera cam = viewOf(s, { 2, 6, 11 }, 61, 47);
  SphereShading shading;
  shading.material.ambient = 0.2;
  shading.material.diffuse = 0.8;
  shading.shadowSide = 3;
  shading.lightCenter = { 1, 9, 2 };
  shading.lightEdgeU = { 2, 0, 0 };
  shading.lightEdgeV = { 0, 0, 2 };
  shading.lightCenterWorld = shading.lightCenter + s.origin;
  shading.aoSamples = 10;
  shading.aoRadius = 1.0;
  Frame frames[2];
  for (int which = 0; which < 2; ++which)
  {
    const std::unique_ptr<SphereAccelerator> accel =
      makeAccelerator(which == 0 ? Accelerators[0] : GetParam(), s);
    RenderStatistics stats;
    renderSpheres({ s, *accel }, viewOf(cam), { shading, 4, 16 }, frames[which], stats);
    EXPECT_GT(stats.counter("shadow_rays"), 0);
    EXPECT_GT(stats.counter("ao_rays"), 0);
  }
  int differ = 0;
  for (std::size_t k = 0; k < frames[0].depth.size(); ++k)
  {
    differ += std::fabs(frames[1].rgba[4 * k] - frames[0].rgba[4 * k]) > 1e-3f ||
              std::fabs(frames[1].depth[k] - frames[0].depth[k]) > 1e-5f;
  }
  // Grazing rays and shadow or occlusion rays that graze a sphere may go either way.
  EXPECT_LE(differ, 20);
}

INSTANTIATE_TEST_SUITE_P(RayPackets, EveryAccelerator, testing::ValuesIn(Accelerators), nameOf);
INSTANTIATE_TEST_SUITE_P(RayPackets,
  EveryEmbreeIsa,
  testing::ValuesIn(std::begin(Accelerators) + 1, std::end(Accelerators)),
  nameOf);
