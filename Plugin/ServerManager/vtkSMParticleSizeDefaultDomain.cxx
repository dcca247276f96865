#include "vtkSMParticleSizeDefaultDomain.h"

#include "vtkObjectFactory.h"
#include "vtkSMDoubleVectorProperty.h"
#include "vtkSMIntVectorProperty.h"
#include "vtkSMParticleSizeArrayDomain.h"
#include "vtkSMProperty.h"
#include "vtkSMPropertyHelper.h"

vtkStandardNewMacro(vtkSMParticleSizeDefaultDomain);

vtkSMParticleSizeDefaultDomain::vtkSMParticleSizeDefaultDomain() = default;

vtkSMParticleSizeDefaultDomain::~vtkSMParticleSizeDefaultDomain() = default;

int vtkSMParticleSizeDefaultDomain::SetDefaultValues(vtkSMProperty* property,
  bool useUncheckedValues)
{
  vtkSMProperty* arrayProperty = this->GetRequiredProperty("ArraySelection");
  auto* arrays =
    arrayProperty ? arrayProperty->FindDomain<vtkSMParticleSizeArrayDomain>() : nullptr;
  if (!arrays)
  {
    vtkErrorMacro("No ArraySelection property with a ParticleSizeArrayDomain.");
    return 0;
  }
  double scale = 1.0;
  const bool found = arrays->GetConventionalArray(scale) != nullptr;
  vtkSMPropertyHelper helper(property);
  helper.SetUseUnchecked(useUncheckedValues);
  if (vtkSMIntVectorProperty::SafeDownCast(property))
  {
    helper.Set(0, found ? 1 : 0);
    return 1;
  }
  if (vtkSMDoubleVectorProperty::SafeDownCast(property))
  {
    helper.Set(0, scale);
    return 1;
  }
  return 0;
}
