/**
 * vtkRayMapperForwardMacro: a representation's setter that hands its value on to the
 * mapper's setter (which checks it) and marks the representation modified, so that the
 * view renders again.
 *
 *   vtkRayMapperForwardMacro(vtkSPHFluidRepresentation, SetDensity, double, SetDensity)
 * defines vtkSPHFluidRepresentation::SetDensity(double) calling Mapper->SetDensity.
 */
#ifndef vtkRayMapperForward_h
#define vtkRayMapperForward_h

#define vtkRayMapperForwardMacro(Class, Method, Type, MapperCall)                                  \
  void Class::Method(Type value)                                                                   \
  {                                                                                                \
    this->Mapper->MapperCall(value);                                                               \
    this->Modified();                                                                              \
  }

#endif
