/**
 * @class   vtkRayMapperParticleVolumeMapper
 * @brief   Abstract base of the RayMappers volume mappers of a vtkPointSet's particles
 *          (vtkRBFVolumeMapper, vtkSPHVolumeMapper, vtkSPHFluidMapper).
 *
 * What the three share: the vtkPointSet input (cells are ignored), the particle size array
 * ScaleArray and its factor ScaleFactor, NumberOfThreads, the statistics of the last render,
 * and the bounds: the finite points' bounds grown on every side by the largest support a
 * particle may have (GetSupportRadius), so that a camera reset frames the whole field.
 * Render runs the subclass's RenderVolume in the mapper's own task arena of NumberOfThreads
 * threads (vtkRayMapperCore::Execute).
 */
#ifndef vtkRayMapperParticleVolumeMapper_h
#define vtkRayMapperParticleVolumeMapper_h

#include "RayMappersMappersModule.h" // for export macro
#include "vtkAbstractVolumeMapper.h"
#include "vtkRayMapperParticleSizes.h" // for SpacingCache
#include "vtkRayMapperSetGet.h"        // for vtkRayMapperScaleMacro

#include <cstddef> // for std::size_t
#include <memory>  // for std::unique_ptr
#include <vector>  // for std::vector

class vtkPointSet;
class vtkRayMapperCore;
class vtkRayMapperStatistics;
class vtkVolumeProperty;
struct vtkRayMapperView;
namespace raymappers
{
struct Light;
struct Material;
}

class RAYMAPPERSMAPPERS_EXPORT vtkRayMapperParticleVolumeMapper : public vtkAbstractVolumeMapper
{
public:
  vtkTypeMacro(vtkRayMapperParticleVolumeMapper, vtkAbstractVolumeMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  void SetInputData(vtkPointSet* input);

  ///@{
  /** The point array of the particles' sizes ScaleArray (first component; none: the
   * subclass's constant) and a factor ScaleFactor on either (default 1; the names of
   * vtkPointGaussianMapper). */
  vtkRayMapperScaleMacro();
  ///@}

  ///@{
  /** NumberOfThreads (vtkRayMapperNumberOfThreadsMacro, vtkRayMapperSetGet.h). */
  vtkRayMapperNumberOfThreadsMacro();
  ///@}

  /**
   * Statistics of the last render: phase times, counters, effects that ran.
   */
  vtkRayMapperStatistics* GetStatistics();

  /**
   * The finite points' bounds grown by GetSupportRadius on every side (uninitialized, with
   * one warning per input change, when there are no finite points).
   */
  double* GetBounds() VTK_SIZEHINT(6) override;
  void GetBounds(double bounds[6]) override { this->vtkAbstractMapper3D::GetBounds(bounds); }

  /**
   * One render: RenderVolume in the mapper's task arena of NumberOfThreads threads; an input
   * without points draws nothing (GetBounds gives its warning).
   */
  void Render(vtkRenderer* ren, vtkVolume* vol) override;
  void ReleaseGraphicsResources(vtkWindow* win) override;

protected:
  /// `drawn` names what the mapper draws in the empty-input warning ("volume", "fluid").
  explicit vtkRayMapperParticleVolumeMapper(const char* drawn);
  ~vtkRayMapperParticleVolumeMapper() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;

  /// The largest distance from a particle's centre at which it still contributes (the
  /// bounds are grown by it); `input` has finite points.
  virtual double GetSupportRadius(vtkPointSet* input) = 0;
  /// The body of one render of `input` (a point set with points), run inside the mapper's
  /// task arena.
  virtual void RenderVolume(vtkRenderer* ren, vtkVolume* vol, vtkPointSet* input) = 0;
  /// After a render that ran out of memory: frees every structure built from the input and
  /// invalidates their stamps (the next render builds them again).
  virtual void ReleaseBuilds() = 0;

  /// The constant particle size in use: `constant` when positive, else the automatic one,
  /// `perSpacing` times the typical spacing of the input's points (vtkRayMapperParticleSizes;
  /// computed again only when the points change).
  double SizeInUse(double constant, double perSpacing);
  /// The warning "<count> <what> and are not drawn." when a build skipped `count` particles.
  void WarnSkipped(std::size_t count, const char* what);
  /// The model transform of `view` (points and normals to world) into a kernel's parameters.
  static void CopyModelTransform(
    const vtkRayMapperView& view, double modelToWorld[16], double normalToWorld[9]);
  /// The volume property's Shade flag; when on, the renderer's lights and the property's
  /// material too.
  static bool GatherShading(vtkRenderer* ren,
    vtkVolumeProperty* property,
    std::vector<raymappers::Light>& lights,
    raymappers::Material& material);

  char* ScaleArray = nullptr;
  double ScaleFactor = 1.0;
  int NumberOfThreads = 0;

  /// The render skeleton: frames, drawer, statistics, camera check, task arena.
  std::unique_ptr<vtkRayMapperCore> Core;

private:
  vtkRayMapperParticleVolumeMapper(const vtkRayMapperParticleVolumeMapper&) = delete;
  void operator=(const vtkRayMapperParticleVolumeMapper&) = delete;

  const char* Drawn;
  vtkRayMapperParticleSizes::SpacingCache Spacing;
};

#endif
