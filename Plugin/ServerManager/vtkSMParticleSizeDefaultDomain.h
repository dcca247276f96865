/**
 * @class   vtkSMParticleSizeDefaultDomain
 * @brief   The default of a property that goes with a particle size array.
 *
 * On the properties beside an array property with a vtkSMParticleSizeArrayDomain, the
 * default follows that domain's conventional array (GetConventionalArray):
 * \li on an IntVectorProperty (e.g. UseRadiusArray): 1 when the input has a conventional
 *     size array, else 0;
 * \li on a DoubleVectorProperty (e.g. RadiusScale): the factor that turns that array's
 *     values into sizes (0.5 for a diameter), 1 when there is no such array.
 * It restricts no value.
 *
 * XML (tag ParticleSizeDefaultDomain): the required property of function "ArraySelection"
 * is the array property, e.g.
 * @code{xml}
 * <ParticleSizeDefaultDomain name="array_default">
 *   <RequiredProperties>
 *     <Property name="RadiusArray" function="ArraySelection" />
 *   </RequiredProperties>
 * </ParticleSizeDefaultDomain>
 * @endcode
 * Its name must sort before the property's other domain ("array_default" before "bool" or
 * "range"): a property keeps its domains in name order, and ParaView's panel makes the
 * widget (a check box, a range) from the last one.
 */
#ifndef vtkSMParticleSizeDefaultDomain_h
#define vtkSMParticleSizeDefaultDomain_h

#include "RayMappersServerManagerModule.h" // for export macro
#include "vtkSMDomain.h"

class RAYMAPPERSSERVERMANAGER_EXPORT vtkSMParticleSizeDefaultDomain : public vtkSMDomain
{
public:
  static vtkSMParticleSizeDefaultDomain* New();
  vtkTypeMacro(vtkSMParticleSizeDefaultDomain, vtkSMDomain);

  /**
   * Sets the property's first element as described above; 0 (nothing set) when the
   * ArraySelection property or its vtkSMParticleSizeArrayDomain is missing.
   */
  int SetDefaultValues(vtkSMProperty* property, bool useUncheckedValues) override;

protected:
  vtkSMParticleSizeDefaultDomain();
  ~vtkSMParticleSizeDefaultDomain() override;

private:
  vtkSMParticleSizeDefaultDomain(const vtkSMParticleSizeDefaultDomain&) = delete;
  void operator=(const vtkSMParticleSizeDefaultDomain&) = delete;
};

#endif
