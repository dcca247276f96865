#include "Mappers/CGT/EmbreeSphereAccelerator.h"
#include "Mappers/Common/EmbreeDevice.h"

#include <limits>

namespace raymappers
{

EmbreeSphereAccelerator::EmbreeSphereAccelerator(const char* deviceConfig)
{
  Device = NewEmbreeDevice(deviceConfig);
}

EmbreeSphereAccelerator::~EmbreeSphereAccelerator()
{
  if (Scene)
  {
    rtcReleaseScene(Scene);
  }
  rtcReleaseDevice(Device);
}

void EmbreeSphereAccelerator::build(const SphereSet& spheres, Quality quality)
{
  clear();
  Count = spheres.size();
  Scene = rtcNewScene(Device);
  const RTCBuildQuality q =
    quality == Quality::Low
      ? RTC_BUILD_QUALITY_LOW
      : (quality == Quality::High ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM);
  rtcSetSceneBuildQuality(Scene, q);
  // Range culling runs as a filter in the intersection context, so changing the ranges
  // needs no rebuild.
  rtcSetSceneFlags(Scene, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  Spheres = &spheres;
  if (Count > 0)
  {
    RTCGeometry geom = rtcNewGeometry(Device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    rtcSetGeometryBuildQuality(geom, q);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), Count));
    if (!v)
    {
      rtcReleaseGeometry(geom);
      clear();
      ThrowOnEmbreeError(Device, "rtcSetNewGeometryBuffer");
      throw std::bad_alloc(); // (no error recorded: the buffer's allocation failed)
    }
    for (std::size_t i = 0; i < Count; ++i)
    {
      v[4 * i] = spheres.centers[i].x;
      v[4 * i + 1] = spheres.centers[i].y;
      v[4 * i + 2] = spheres.centers[i].z;
      v[4 * i + 3] = spheres.radii[i];
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometry(Scene, geom);
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(Scene);
  const RTCError error = rtcGetDeviceError(Device);
  if (error != RTC_ERROR_NONE) // (a failed commit leaves no scene to trace)
  {
    clear();
    ThrowEmbreeError(error, "rtcCommitScene");
  }
}

void EmbreeSphereAccelerator::clear()
{
  if (Scene)
  {
    rtcReleaseScene(Scene);
    Scene = nullptr;
  }
  Count = 0;
  Spheres = nullptr;
}

namespace
{
// The ray of lanes left out: finite, and the empty interval [1, 0].
const Ray EmptyRay{ Vec3f(0.f, 0.f, 0.f), Vec3f(0.f, 0.f, 1.f), 1.f, 0.f };

// The intersection context with what the filter needs; Embree hands the context back to the
// filter callback.
struct FilterContext
{
  RTCIntersectContext context;
  const RangeFilter* filter; // null: no parameter ranges
  const SphereSet* spheres;
  std::int64_t rejected;
  // Ordered packets (RayPacket::ordered): the 16 rays' tnear and tieFrom, and the best hit
  // accepted so far in (t, index) order (Embree offers hits with tnear <= t <= tfar, ties at
  // the best one's t included, and makes an accepted hit's t the ray's new tfar).
  bool ordered;
  float tnear[16];
  std::uint32_t tieFrom[16];
  float bestT[16];
  std::uint32_t bestPrim[16];
};

// Rejects candidate hits on spheres outside the parameter ranges and, for ordered packets,
// those not after (tnear, tieFrom - 1) or not before the best hit in (t, index) order.
void filterCallback(const RTCFilterFunctionNArguments* args)
{
  auto* ctx = reinterpret_cast<FilterContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i)
  {
    if (args->valid[i] != -1)
    {
      continue;
    }
    const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
    if (ctx->filter && !ctx->filter->passes(ctx->spheres->attributesOf(prim)))
    {
      args->valid[i] = 0;
      ++ctx->rejected;
      continue;
    }
    if (!ctx->ordered)
    {
      continue;
    }
    const unsigned k = RTCRayN_id(args->ray, args->N, i);
    const float t = RTCRayN_tfar(args->ray, args->N, i); // the candidate's distance
    const bool after = t > ctx->tnear[k] || prim >= ctx->tieFrom[k];
    const bool before = t < ctx->bestT[k] || (t == ctx->bestT[k] && prim < ctx->bestPrim[k]);
    if (after && before)
    {
      ctx->bestT[k] = t;
      ctx->bestPrim[k] = prim;
    }
    else
    {
      args->valid[i] = 0;
    }
  }
}
}

void EmbreeSphereAccelerator::intersect(const RayPacket& packet,
  PacketHits& hits,
  TraversalCounters& counters) const
{
  FilterContext filter;
  rtcInitIntersectContext(&filter.context);
  filter.context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  const bool ranged = Filter.count > 0 && Spheres && Filter.count <= Spheres->numAttributes;
  filter.filter = ranged ? &Filter : nullptr;
  filter.spheres = Spheres;
  filter.rejected = 0;
  filter.ordered = packet.ordered;
  if (ranged || packet.ordered)
  {
    filter.context.filter = &filterCallback;
  }
  const int n = packet.side * packet.side;
  alignas(64) RTCRayHit16 rh;
  alignas(64) int valid[16];
  for (int base = 0; base < n; base += 16)
  {
    if (toEmbreePacket(packet, base, rh, valid))
    {
      for (int k = 0; k < 16 && packet.ordered; ++k)
      {
        filter.tnear[k] = rh.ray.tnear[k];
        filter.bestT[k] = rh.ray.tfar[k];
        filter.tieFrom[k] = base + k < n ? packet.tieFrom[base + k] : 0;
        filter.bestPrim[k] = NoHit;
      }
      rtcIntersect16(valid, Scene, &filter.context, &rh);
      counters.rangeCulled += filter.rejected;
      filter.rejected = 0;
    }
    for (int k = 0; k < 16 && base + k < n; ++k)
    {
      const int lane = base + k;
      const bool hit = valid[k] && rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
      hits.prim[lane] = hit ? rh.hit.primID[k] : NoHit;
      hits.t[lane] = hit ? rh.ray.tfar[k] : 0.f;
    }
  }
}

int EmbreeSphereAccelerator::occluded(const RayPacket& packet,
  bool* blocked,
  TraversalCounters& counters) const
{
  FilterContext ranges;
  rtcInitIntersectContext(&ranges.context);
  ranges.context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  const bool ranged = Filter.count > 0 && Spheres && Filter.count <= Spheres->numAttributes;
  ranges.filter = ranged ? &Filter : nullptr;
  ranges.spheres = Spheres;
  ranges.rejected = 0;
  ranges.ordered = false; // any hit
  if (ranged)
  {
    ranges.context.filter = &filterCallback;
  }
  const int n = packet.side * packet.side;
  alignas(64) RTCRayHit16 rh;
  alignas(64) int valid[16];
  int count = 0;
  for (int base = 0; base < n; base += 16)
  {
    const bool any = toEmbreePacket(packet, base, rh, valid);
    if (any)
    {
      // rtcOccluded16 sets tfar to -inf on the lanes that meet something.
      rtcOccluded16(valid, Scene, &ranges.context, &rh.ray);
      counters.rangeCulled += ranges.rejected;
      ranges.rejected = 0;
    }
    for (int k = 0; k < 16 && base + k < n; ++k)
    {
      const bool hit = any && valid[k] && rh.ray.tfar[k] == -std::numeric_limits<float>::infinity();
      blocked[base + k] = hit;
      count += hit ? 1 : 0;
    }
  }
  return count;
}

bool EmbreeSphereAccelerator::toEmbreePacket(const RayPacket& packet,
  int base,
  RTCRayHit16& rh,
  int* valid)
{
  const int n = packet.side * packet.side;
  bool any = false;
  for (int k = 0; k < 16; ++k)
  {
    const int lane = base + k;
    const bool traced = lane < n && packet.valid[lane] && isTraceable(packet.rays[lane]);
    valid[k] = traced ? -1 : 0;
    any = any || traced;
    // Every lane is written. Embree traces a 16-ray packet on CPUs without AVX-512 through
    // its ray-stream code, which ignores the valid mask and traces each lane whose tnear <=
    // tfar: a lane left out is the empty interval [1, 0] on a finite ray.
    const Ray& r = traced ? packet.rays[lane] : EmptyRay;
    rh.ray.org_x[k] = r.org.x;
    rh.ray.org_y[k] = r.org.y;
    rh.ray.org_z[k] = r.org.z;
    rh.ray.dir_x[k] = r.dir.x;
    rh.ray.dir_y[k] = r.dir.y;
    rh.ray.dir_z[k] = r.dir.z;
    rh.ray.tnear[k] = r.tnear;
    rh.ray.tfar[k] = r.tfar;
    rh.ray.time[k] = 0.f;
    rh.ray.mask[k] = 0xFFFFFFFFu;
    rh.ray.id[k] = static_cast<unsigned>(k);
    rh.ray.flags[k] = 0;
    rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID[k] = RTC_INVALID_GEOMETRY_ID;
  }
  return any;
}

} // namespace raymappers
