// Embree reports failures through its device's error code, not exceptions: ThrowOnEmbreeError
// turns the pending code into the exception the mappers' render catches (vtkRayMapperCore::
// Execute), std::bad_alloc for RTC_ERROR_OUT_OF_MEMORY (a structure that does not fit) and
// std::runtime_error naming the step for any other.
#ifndef RayMappers_EmbreeErrors_h
#define RayMappers_EmbreeErrors_h

#include <embree3/rtcore.h>

#include <new>
#include <stdexcept>
#include <string>

namespace raymappers
{

/// Throws for `error`, which `step` (the Embree call) gave.
[[noreturn]] inline void ThrowEmbreeError(RTCError error, const char* step)
{
  if (error == RTC_ERROR_OUT_OF_MEMORY)
  {
    throw std::bad_alloc();
  }
  throw std::runtime_error(std::string("Embree: ") + step + " failed (error " +
                           std::to_string(static_cast<int>(error)) + ")");
}

/// Throws for the error Embree recorded on `device` since the last query, if any (nullptr:
/// the error of a device that could not be created).
inline void ThrowOnEmbreeError(RTCDevice device, const char* step)
{
  const RTCError error = rtcGetDeviceError(device);
  if (error != RTC_ERROR_NONE)
  {
    ThrowEmbreeError(error, step);
  }
}

}

#endif
