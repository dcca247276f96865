# The parsers of RayMappers::IO: plain C++17 with std only (no VTK header), built as one
# static library that the VTK module links privately and the kernel unit tests
# (Testing/Cxx/Kernels) link directly. They live beside their vtk* readers.
add_library(RayMappersIOKernels STATIC
  ${CMAKE_CURRENT_LIST_DIR}/LAMMPS/LammpsDumpParser.cxx)
target_include_directories(RayMappersIOKernels PUBLIC "$<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>")
target_compile_features(RayMappersIOKernels PUBLIC cxx_std_17)
target_compile_options(RayMappersIOKernels PRIVATE ${RAYMAPPERS_WARNINGS})
set_target_properties(RayMappersIOKernels PROPERTIES
  POSITION_INDEPENDENT_CODE ON
  CXX_STANDARD 17
  CXX_STANDARD_REQUIRED ON
  CXX_EXTENSIONS OFF)
