// The world-to-clip matrix of a vtkCamera for an image of a given aspect ratio, row-major
// with column vectors (p_clip = M p), OpenGL's clip coordinates (z in [-1, 1]): the matrix a
// kernel's View is made from when there is no renderer to ask (a filter such as
// vtkSPHVoxelizer, or a renderer without an OpenGL camera).
#ifndef vtkRayMapperCameraMatrix_h
#define vtkRayMapperCameraMatrix_h

#include "RayMappersCoreModule.h" // for export macro

#include <array>

class vtkCamera;

/// vtkCamera::GetCompositeProjectionTransformMatrix(aspect, -1, 1) as a row-major array.
RAYMAPPERSCORE_EXPORT std::array<double, 16> vtkRayMapperWorldToClip(vtkCamera* camera, double aspect);

#endif
