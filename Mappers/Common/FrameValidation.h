// The check of a kernel's float frame (Frame.h) that vtkRayMapperStatistics::ValidateFrames
// turns on: a valid frame holds premultiplied RGBA and window depth, so every value is
// finite, 0 <= alpha <= 1, 0 <= colour <= alpha and 0 <= depth <= 1. The PNG of a test
// cannot show a violation (the GPU clamps and rounds), the float frame does.
#ifndef RayMappers_FrameValidation_h
#define RayMappers_FrameValidation_h

#include "Mappers/Common/Frame.h"

#include <cstdint>

namespace raymappers
{

struct FrameValidation
{
  std::int64_t nonFinite = 0;  // NaN or infinite values of rgba or depth
  std::int64_t outOfRange = 0; // finite values outside their range (see validateFrame)
};

/// How far a premultiplied colour channel may exceed its alpha (or go below 0) before it
/// counts as out of range: float rounding of a shaded colour times alpha stays far below.
constexpr float FrameColorTolerance = 1e-5f;

/// Counts the values of `frame` that are not finite, and the finite ones out of range: an
/// alpha outside [0, 1], a colour channel below -FrameColorTolerance or above its pixel's
/// alpha + FrameColorTolerance, a depth outside [0, 1]. Each value counts once.
FrameValidation validateFrame(const Frame& frame);

} // namespace raymappers

#endif
