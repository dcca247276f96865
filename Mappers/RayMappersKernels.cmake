# The kernels of every method: plain C++17 with std, Embree and TBB only (no VTK header),
# built as one shared library that the VTK modules RayMappers::Mappers and
# RayMappers::Filters link privately and the kernel unit tests link directly: linked once, so
# a process that loads both modules holds one copy of each kernel. They live beside their
# vtk* adapters, one folder per method.
add_library(RayMappersKernels SHARED
  ${CMAKE_CURRENT_LIST_DIR}/Common/FrameValidation.cxx
  ${CMAKE_CURRENT_LIST_DIR}/Common/RayCamera.cxx
  ${CMAKE_CURRENT_LIST_DIR}/Common/RenderStatistics.cxx
  ${CMAKE_CURRENT_LIST_DIR}/Common/TransferFunctionTable.cxx
  ${CMAKE_CURRENT_LIST_DIR}/Common/Lighting.cxx
  ${CMAKE_CURRENT_LIST_DIR}/CGT/CoherentGrid.cxx
  ${CMAKE_CURRENT_LIST_DIR}/CGT/CoherentGridAccelerator.cxx
  ${CMAKE_CURRENT_LIST_DIR}/CGT/EmbreeSphereAccelerator.cxx
  ${CMAKE_CURRENT_LIST_DIR}/CGT/RaySphereLanes.cxx
  ${CMAKE_CURRENT_LIST_DIR}/CGT/SphereRenderer.cxx
  ${CMAKE_CURRENT_LIST_DIR}/RBF/ParticleBVH.cxx
  ${CMAKE_CURRENT_LIST_DIR}/RBF/RBFVolumeRenderer.cxx
  ${CMAKE_CURRENT_LIST_DIR}/RBF/RBFDirectMethod.cxx
  ${CMAKE_CURRENT_LIST_DIR}/RBF/RBFCoherentMethod.cxx
  ${CMAKE_CURRENT_LIST_DIR}/ZSweep/OpticalModel.cxx
  ${CMAKE_CURRENT_LIST_DIR}/ZSweep/ZSweepMesh.cxx
  ${CMAKE_CURRENT_LIST_DIR}/ZSweep/ZSweepNearPlane.cxx
  ${CMAKE_CURRENT_LIST_DIR}/ZSweep/ZSweepRenderer.cxx
  ${CMAKE_CURRENT_LIST_DIR}/Common/ViewRays.cxx
  ${CMAKE_CURRENT_LIST_DIR}/Common/View.cxx
  ${CMAKE_CURRENT_LIST_DIR}/SPH/PerspectiveGrid.cxx
  ${CMAKE_CURRENT_LIST_DIR}/SPH/SPHVolumeRenderer.cxx
  ${CMAKE_CURRENT_LIST_DIR}/SPH/FluidCells.cxx
  ${CMAKE_CURRENT_LIST_DIR}/SPH/SpanVoxelizer.cxx
  ${CMAKE_CURRENT_LIST_DIR}/SPH/SurfaceLinks.cxx
  ${CMAKE_CURRENT_LIST_DIR}/SPH/FluidRenderer.cxx)
# Includes are path-prefixed from the source root ("Mappers/CGT/SphereSet.h"), so a kernel
# header's name says its method and no bare "Frame.h" reaches a consumer.
target_include_directories(RayMappersKernels PUBLIC "$<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>")
target_link_libraries(RayMappersKernels PUBLIC embree TBB::tbb)
# -fopenmp-simd: the `#pragma omp simd` loops over a packet's rays. -fno-math-errno: a
# std::sqrt that may set errno is a call the vectorizer cannot put in SIMD lanes (no kernel
# reads errno).
target_compile_options(RayMappersKernels PRIVATE ${RAYMAPPERS_WARNINGS} -fopenmp-simd -fno-math-errno)
if (RAYMAPPERS_NATIVE)
  target_compile_options(RayMappersKernels PRIVATE -march=native)
endif ()
set_target_properties(RayMappersKernels PROPERTIES POSITION_INDEPENDENT_CODE ON)
# Beside the VTK modules' libraries: the plugin's libraries find it two folders up
# (paraview-plugins/RayMappers/ -> lib/).
install(TARGETS RayMappersKernels LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}")
