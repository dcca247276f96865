#include "EmbreeSphereAccelerator.h"

#include <stdexcept>
#include <string>

namespace raymappers
{

EmbreeSphereAccelerator::EmbreeSphereAccelerator()
{
  Device = rtcNewDevice(nullptr);
  if (!Device)
  {
    throw std::runtime_error("Embree: rtcNewDevice failed (error " +
                             std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
  }
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
  if (Scene)
  {
    rtcReleaseScene(Scene);
    Scene = nullptr;
  }
  Count = spheres.size();
  Scene = rtcNewScene(Device);
  const RTCBuildQuality q =
    quality == Quality::Low
      ? RTC_BUILD_QUALITY_LOW
      : (quality == Quality::High ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM);
  rtcSetSceneBuildQuality(Scene, q);
  rtcSetSceneFlags(Scene, RTC_SCENE_FLAG_NONE);
  if (Count > 0)
  {
    RTCGeometry geom = rtcNewGeometry(Device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    rtcSetGeometryBuildQuality(geom, q);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), Count));
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
}

void EmbreeSphereAccelerator::intersect16(const int* valid, RTCRayHit16& rayhit) const
{
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  rtcIntersect16(valid, Scene, &context, &rayhit);
}

} // namespace raymappers
