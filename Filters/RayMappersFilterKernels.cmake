# The kernels of RayMappers::Filters: plain C++17 with std only (no VTK header), built as
# one static library that the VTK module links privately and the kernel unit tests
# (Testing/Cxx/Kernels) link directly. They live beside their vtk* adapters.
add_library(RayMappersFilterKernels STATIC
  ${CMAKE_CURRENT_LIST_DIR}/LAMMPS/LammpsDumpParser.cxx)
target_include_directories(RayMappersFilterKernels PUBLIC
  ${CMAKE_CURRENT_LIST_DIR}/LAMMPS)
target_compile_features(RayMappersFilterKernels PUBLIC cxx_std_17)
target_compile_options(RayMappersFilterKernels PRIVATE ${RAYMAPPERS_WARNINGS})
set_target_properties(RayMappersFilterKernels PROPERTIES
  POSITION_INDEPENDENT_CODE ON
  CXX_STANDARD 17
  CXX_STANDARD_REQUIRED ON
  CXX_EXTENSIONS OFF)
