# The kernels of every method: plain C++17 with std, Embree and TBB only (no VTK header),
# built as one shared library that the VTK modules RayMappers::Mappers and
# RayMappers::Filters link privately and the kernel unit tests link directly: linked once, so
# a process that loads both modules holds one copy of each kernel. They live beside their
# vtk* adapters, one folder per method.
#
# The hot kernels, compiled once more per SIMD instruction set in the default build (below).
set(RAYMAPPERS_DISPATCHED_KERNELS
  ${CMAKE_CURRENT_LIST_DIR}/RBF/RBFDirectMethod.cxx
  ${CMAKE_CURRENT_LIST_DIR}/RBF/RBFCoherentMethod.cxx
  ${CMAKE_CURRENT_LIST_DIR}/SPH/SPHVolumeRenderer.cxx
  ${CMAKE_CURRENT_LIST_DIR}/SPH/SpanVoxelizer.cxx
  ${CMAKE_CURRENT_LIST_DIR}/SPH/FluidRenderer.cxx
  ${CMAKE_CURRENT_LIST_DIR}/ZSweep/OpticalModel.cxx
  ${CMAKE_CURRENT_LIST_DIR}/ZSweep/ZSweepRenderer.cxx)
add_library(RayMappersKernels SHARED
  ${RAYMAPPERS_DISPATCHED_KERNELS}
  ${CMAKE_CURRENT_LIST_DIR}/Common/AvailableMemory.cxx
  ${CMAKE_CURRENT_LIST_DIR}/Common/FrameValidation.cxx
  ${CMAKE_CURRENT_LIST_DIR}/Common/RayCamera.cxx
  ${CMAKE_CURRENT_LIST_DIR}/Common/RenderStatistics.cxx
  ${CMAKE_CURRENT_LIST_DIR}/Common/TransferFunctionTable.cxx
  ${CMAKE_CURRENT_LIST_DIR}/Common/Lighting.cxx
  ${CMAKE_CURRENT_LIST_DIR}/CGT/CoherentGrid.cxx
  ${CMAKE_CURRENT_LIST_DIR}/CGT/CoherentGridAccelerator.cxx
  ${CMAKE_CURRENT_LIST_DIR}/CGT/EmbreeSphereAccelerator.cxx
  ${CMAKE_CURRENT_LIST_DIR}/CGT/RaySphereLanes.cxx
  ${CMAKE_CURRENT_LIST_DIR}/CGT/SphereOcclusion.cxx
  ${CMAKE_CURRENT_LIST_DIR}/CGT/SphereRenderer.cxx
  ${CMAKE_CURRENT_LIST_DIR}/RBF/ParticleBVH.cxx
  ${CMAKE_CURRENT_LIST_DIR}/RBF/RBFVolumeRenderer.cxx
  ${CMAKE_CURRENT_LIST_DIR}/ZSweep/ZSweepMesh.cxx
  ${CMAKE_CURRENT_LIST_DIR}/ZSweep/IsoparametricCell.cxx
  ${CMAKE_CURRENT_LIST_DIR}/ZSweep/ZSweepNearPlane.cxx
  ${CMAKE_CURRENT_LIST_DIR}/Common/ViewRays.cxx
  ${CMAKE_CURRENT_LIST_DIR}/Common/View.cxx
  ${CMAKE_CURRENT_LIST_DIR}/SPH/PerspectiveGrid.cxx
  ${CMAKE_CURRENT_LIST_DIR}/SPH/FluidCells.cxx
  ${CMAKE_CURRENT_LIST_DIR}/SPH/FluidColors.cxx
  ${CMAKE_CURRENT_LIST_DIR}/SPH/SurfaceLinks.cxx)
# Includes are path-prefixed from the source root ("Mappers/CGT/SphereSet.h"), so a kernel
# header's name says its method and no bare "Frame.h" reaches a consumer.
target_include_directories(RayMappersKernels PUBLIC "$<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>")
target_link_libraries(RayMappersKernels PUBLIC embree TBB::tbb)
# -fopenmp-simd: the `#pragma omp simd` loops over a packet's rays. -fno-math-errno: a
# std::sqrt that may set errno is a call the vectorizer cannot put in SIMD lanes (no kernel
# reads errno). -ffp-contract=off: a*b+c stays a multiply and an add where the instruction
# set has FMA, so every SIMD variant (and the portable build) computes the same floats.
set(RAYMAPPERS_KERNEL_OPTIONS ${RAYMAPPERS_WARNINGS} -fopenmp-simd -fno-math-errno -ffp-contract=off)
target_compile_options(RayMappersKernels PRIVATE ${RAYMAPPERS_KERNEL_OPTIONS})
set_target_properties(RayMappersKernels PROPERTIES POSITION_INDEPENDENT_CODE ON)
if (RAYMAPPERS_NATIVE)
  target_compile_options(RayMappersKernels PRIVATE -march=native)
elseif (CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64|amd64)$")
  # Run-time dispatch (Common/SimdTarget.h): the hot kernels are compiled twice more, for
  # AVX2 (RAYMAPPERS_SIMD_TARGET=2) and AVX-512 (3), into object libraries linked into the
  # kernel library; the copy compiled with the default flags chooses among them per frame.
  foreach (simd_target IN ITEMS 2 3)
    set(variant RayMappersKernelsSimd${simd_target})
    add_library(${variant} OBJECT ${RAYMAPPERS_DISPATCHED_KERNELS})
    target_include_directories(${variant} PRIVATE
      $<TARGET_PROPERTY:RayMappersKernels,INCLUDE_DIRECTORIES>)
    target_link_libraries(${variant} PRIVATE embree TBB::tbb)
    target_compile_options(${variant} PRIVATE ${RAYMAPPERS_KERNEL_OPTIONS})
    target_compile_definitions(${variant} PRIVATE
      RAYMAPPERS_SIMD_DISPATCH=1 RAYMAPPERS_SIMD_TARGET=${simd_target})
    set_target_properties(${variant} PROPERTIES POSITION_INDEPENDENT_CODE ON)
    if (simd_target EQUAL 3)
      # Vector gathers for the table lookups in SIMD loops (transfer functions, ZSweep's
      # intervals): every AVX-512 CPU runs them fast, so here they beat -mtune=generic's
      # scalar loads (whose choice guards older AVX2 CPUs). Tuning only: the code that
      # runs on any x86-64 stays the same.
      target_compile_options(${variant} PRIVATE -mtune-ctrl=use_gather)
    endif ()
    target_sources(RayMappersKernels PRIVATE $<TARGET_OBJECTS:${variant}>)
  endforeach ()
  target_compile_definitions(RayMappersKernels PRIVATE RAYMAPPERS_SIMD_DISPATCH=1)
endif ()
# Beside the VTK modules' libraries: the plugin's libraries find it two folders up
# (paraview-plugins/RayMappers/ -> lib/).
install(TARGETS RayMappersKernels LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}")
