// The largest magnitude a length (a particle's radius or support, a distance property) or a
// factor on lengths may have in the kernels. They compute in float (largest 3.4e38) with
// origin-relative coordinates and square lengths (ray-sphere tests, Gaussians, kernel
// supports): 1e15 keeps a square (1e30) and the sum of a few such terms finite, with room
// for their products with the data's own extent; a length of 1e19 or more would overflow to
// infinity in a square and turn into NaN further on. vtkRayMapperSetGet.h clamps the
// properties to it, ParticleInput.h skips particles beyond it.
#ifndef RayMappers_Limits_h
#define RayMappers_Limits_h

namespace raymappers
{

constexpr double MaxLength = 1e15;

} // namespace raymappers

#endif
