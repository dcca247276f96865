// raymappers-reference: renders the reference picture of a scene file (written by the
// pvpython tests, Testing/Python/raymappers_reference.py) with ReferenceRenderers.h.
//
//   raymappers-reference SCENE.txt OUTPUT.raw
//
// The scene is one directive a line ('#' starts a comment):
//   camera W H m00 m01 ... m33         world-to-NDC matrix, row-major
//   render spheres|translucent|union|rbf|sph  which picture (translucent: the spheres
//                                       composited with their opacities)
//   light tx ty tz r g b                a directional light: unit vector to it, colour
//   material ambient diffuse specular power sr sg sb
//   sphere x y z radius r g b [opacity]  (opacity 1 when left out)
//   gaussian x y z radius weight
//   rbf kappa cutoff step [sum|average]  (sum when left out; average: normalized weights)
//   sph_particle x y z support quantity volume
//   sph poly6|cubic|wendland normalized|unnormalized step
//   transfer lo hi unit_distance n      then n lines "r g b a"
//   tetra x0 y0 z0 s0 ... x3 y3 z3 s3   a tetrahedron, its corners with their point scalars
//   nodes unit_distance n               then n lines "s r g b a": the piecewise-linear
//                                       transfer function of "render unstructured"
// The output holds W x H x 5 doubles (premultiplied r, g, b, a and the window depth per
// pixel, rows from the bottom), native byte order.
#include "ReferenceRenderers.h"
#include "UnstructuredReference.h"

#include <tbb/parallel_for.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

using namespace raymappers::reference;

namespace
{
struct Scene
{
  int width = 0, height = 0;
  std::array<double, 16> matrix{};
  std::string render;
  std::vector<ReferenceLight> lights;
  ReferenceMaterial material;
  std::vector<ReferenceSphere> spheres;
  std::vector<ReferenceGaussian> gaussians;
  RBFReference rbf;
  std::vector<ReferenceSPHParticle> sph;
  SPHReference sphParams;
  ReferenceTransferFunction tf;
  std::vector<raymappers::test::RefTetra> tetrahedra;
  raymappers::test::RefTransferFunction nodes;
};

ReferenceKernel kernelNamed(const std::string& name)
{
  if (name == "poly6")
  {
    return ReferenceKernel::Poly6;
  }
  if (name == "cubic")
  {
    return ReferenceKernel::CubicSpline;
  }
  if (name == "wendland")
  {
    return ReferenceKernel::WendlandC2;
  }
  throw std::runtime_error("unknown kernel " + name);
}

// One directive; the transfer function's table lines come from `in`.
void readDirective(const std::string& key, std::istringstream& words, std::istream& in, Scene& s)
{
  if (key == "camera")
  {
    words >> s.width >> s.height;
    for (double& m : s.matrix)
    {
      words >> m;
    }
  }
  else if (key == "render")
  {
    words >> s.render;
  }
  else if (key == "light")
  {
    ReferenceLight l;
    words >> l.toLight.x >> l.toLight.y >> l.toLight.z >> l.color.x >> l.color.y >> l.color.z;
    s.lights.push_back(l);
  }
  else if (key == "material")
  {
    ReferenceMaterial& m = s.material;
    words >> m.ambient >> m.diffuse >> m.specular >> m.specularPower >> m.specularColor.x >>
      m.specularColor.y >> m.specularColor.z;
  }
  else if (key == "sphere")
  {
    ReferenceSphere b;
    words >> b.center.x >> b.center.y >> b.center.z >> b.radius >> b.color.x >> b.color.y >>
      b.color.z;
    if (!words.eof() && !(words >> std::ws).eof())
    {
      words >> b.opacity;
    }
    s.spheres.push_back(b);
  }
  else if (key == "gaussian")
  {
    ReferenceGaussian g;
    words >> g.center.x >> g.center.y >> g.center.z >> g.radius >> g.weight;
    s.gaussians.push_back(g);
  }
  else if (key == "rbf")
  {
    std::string value;
    words >> s.rbf.kappa >> s.rbf.cutoff >> s.rbf.step >> value;
    s.rbf.average = value == "average";
  }
  else if (key == "sph_particle")
  {
    ReferenceSPHParticle p;
    words >> p.center.x >> p.center.y >> p.center.z >> p.support >> p.quantity >> p.volume;
    s.sph.push_back(p);
  }
  else if (key == "sph")
  {
    std::string kernel, normalization;
    words >> kernel >> normalization >> s.sphParams.step;
    s.sphParams.kernel = kernelNamed(kernel);
    s.sphParams.normalized = normalization == "normalized";
  }
  else if (key == "transfer")
  {
    int n = 0;
    words >> s.tf.lo >> s.tf.hi >> s.tf.unitDistance >> n;
    s.tf.rgba.resize(n);
    for (auto& c : s.tf.rgba)
    {
      in >> c[0] >> c[1] >> c[2] >> c[3];
    }
  }
  else if (key == "tetra")
  {
    raymappers::test::RefTetra t;
    for (std::size_t k = 0; k < 4; ++k)
    {
      words >> t.p[k].x >> t.p[k].y >> t.p[k].z >> t.s[k];
    }
    s.tetrahedra.push_back(t);
  }
  else if (key == "nodes")
  {
    int n = 0;
    words >> s.nodes.unitDistance >> n;
    for (int k = 0; k < n; ++k)
    {
      double v = 0, r = 0, g = 0, b = 0, a = 0;
      in >> v >> r >> g >> b >> a;
      s.nodes.s.push_back(v);
      s.nodes.rgb.insert(s.nodes.rgb.end(), { r, g, b });
      s.nodes.alpha.push_back(a);
    }
  }
  else
  {
    throw std::runtime_error("unknown directive " + key);
  }
  if (words.fail())
  {
    throw std::runtime_error("malformed directive " + key);
  }
}

Scene readScene(const std::string& path)
{
  std::ifstream in(path);
  if (!in)
  {
    throw std::runtime_error("cannot read " + path);
  }
  Scene s;
  std::string line;
  while (std::getline(in, line))
  {
    line = line.substr(0, line.find('#'));
    std::istringstream words(line);
    std::string key;
    if (words >> key)
    {
      readDirective(key, words, in, s);
    }
  }
  if (s.width <= 0 || s.height <= 0)
  {
    throw std::runtime_error("no camera in " + path);
  }
  return s;
}

// The tetrahedra's picture (UnstructuredReference.h: every tetrahedron the ray meets clipped
// in double, the segments integrated between the transfer function's nodes, Simpson's rule
// with 64 intervals a piece); the depth stays at the far plane.
ReferenceImage renderUnstructured(const ReferenceCamera& camera, const Scene& s)
{
  if (s.tetrahedra.empty() || s.nodes.s.empty())
  {
    throw std::runtime_error("render unstructured needs tetra and nodes directives");
  }
  const raymappers::test::ReferenceTetraGrid cells(s.tetrahedra);
  ReferenceImage image(camera.width(), camera.height());
  tbb::parallel_for(0,
    camera.height(),
    [&](int j)
    {
      std::vector<std::size_t> candidates;
      for (int i = 0; i < camera.width(); ++i)
      {
        const PixelRay ray = camera.ray(i, j);
        const raymappers::Vec3d o(ray.origin.x, ray.origin.y, ray.origin.z);
        const raymappers::Vec3d d(ray.direction.x, ray.direction.y, ray.direction.z);
        cells.candidates(o, d, 0.0, candidates);
        image.at(i, j) =
          raymappers::test::traceReference(s.tetrahedra, false, s.nodes, o, d, 0.0, &candidates, 64);
      }
    });
  return image;
}

ReferenceImage render(const Scene& s)
{
  const ReferenceCamera camera(s.matrix, s.width, s.height);
  if (s.render == "spheres")
  {
    return renderSpheres(camera, s.spheres, s.lights, s.material);
  }
  if (s.render == "translucent")
  {
    return renderTranslucentSpheres(camera, s.spheres, s.lights, s.material, {});
  }
  if (s.render == "union")
  {
    return renderUnionSurface(camera, s.spheres);
  }
  if (s.render == "rbf")
  {
    return renderRBF(camera, s.gaussians, s.rbf, s.tf);
  }
  if (s.render == "sph")
  {
    return renderSPH(camera, s.sph, s.sphParams, s.tf);
  }
  if (s.render == "unstructured")
  {
    return renderUnstructured(camera, s);
  }
  throw std::runtime_error("unknown picture '" + s.render + "'");
}
}

int main(int argc, char* argv[])
{
  if (argc != 3)
  {
    std::fprintf(stderr, "usage: raymappers-reference SCENE.txt OUTPUT.raw\n");
    return 2;
  }
  try
  {
    const ReferenceImage image = render(readScene(argv[1]));
    std::ofstream out(argv[2], std::ios::binary);
    for (std::size_t p = 0; p < image.rgba.size(); ++p)
    {
      out.write(reinterpret_cast<const char*>(image.rgba[p].data()), 4 * sizeof(double));
      out.write(reinterpret_cast<const char*>(&image.depth[p]), sizeof(double));
    }
    return out ? 0 : 2;
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "raymappers-reference: %s\n", e.what());
    return 2;
  }
}
