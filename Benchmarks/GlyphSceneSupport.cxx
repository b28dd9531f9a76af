// SPDX-License-Identifier: BSD-3-Clause
#include "GlyphSceneSupport.h"

#include "sightline/core/Renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace sightline_benchmark
{
using sightline::Box3;
using sightline::dvec3;
using sightline::vec3;

namespace
{
using sightline::kPi;
} // namespace

View makeGlyphView(const std::vector<vec3>& centers, double glyphRadius, int width, int height)
{
  Box3 box;
  for (const vec3& c : centers)
    box.extend(c);
  const dvec3 margin(glyphRadius + 0.1);
  const dvec3 lower = dvec3(box.lower) - margin, upper = dvec3(box.upper) + margin;
  const dvec3 focal = 0.5 * (lower + upper);
  const double tilt = kTiltDegrees * kPi / 180.0;
  const dvec3 toCamera(0.0, -std::sin(tilt), std::cos(tilt));
  View view;
  view.width = width;
  view.height = height;
  sightline::CameraParameters& p = view.parameters;
  p.focalPoint = focal;
  p.viewUp = dvec3(0.0, std::cos(tilt), std::sin(tilt));
  p.viewAngle = 30.0;
  const double aspect = double(width) / height;
  // The nearest distance at which every corner of the slice's box is inside 95 % of the frame.
  auto fits = [&](double distance)
  {
    p.position = focal + distance * toCamera;
    const double extent = glm::length(upper - lower);
    p.nearClip = std::max(1e-3, distance - extent);
    p.farClip = distance + extent;
    const sightline::dmat4 m = sightline::Camera::worldToClipMatrix(p, aspect);
    for (int corner = 0; corner < 8; ++corner)
    {
      const dvec3 q((corner & 1) ? upper.x : lower.x, (corner & 2) ? upper.y : lower.y,
        (corner & 4) ? upper.z : lower.z);
      const sightline::dvec4 clip = m * sightline::dvec4(q, 1.0);
      if (clip.w <= 0.0 || std::abs(clip.x / clip.w) > 0.95 || std::abs(clip.y / clip.w) > 0.95)
        return false;
    }
    return true;
  };
  double near = 0.1, far = 1e6;
  for (int iteration = 0; iteration < 100; ++iteration)
  {
    const double middle = std::sqrt(near * far);
    (fits(middle) ? far : near) = middle;
  }
  fits(far);
  // One directional light from the upper left behind the camera, so shadows fall visibly.
  view.lighting.lights.push_back({ vec3(glm::normalize(dvec3(0.45, 0.35, -1.0))), vec3(1.0f), 1.0f });
  return view;
}

sightline::Camera makeCamera(const View& view)
{
  return sightline::Camera::fromParameters(view.parameters, view.width, view.height);
}

sightline::Material glyphMaterial()
{
  sightline::Material material;
  material.model = sightline::ShadingModel::GltfDielectric;
  material.roughness = 0.45f;
  material.ambient = 0.15f;
  material.diffuse = 1.0f;
  material.specular = 1.0f;
  return material;
}

BuiltScene::BuiltScene(std::shared_ptr<const sightline::Geometry> geometry)
{
  scene = std::make_unique<sightline::EmbreeScene>(device);
  if (geometry)
    scene->add(std::move(geometry));
  scene->commit();
}

std::string fixed(double value, int precision)
{
  if (!std::isfinite(value))
    return "-";
  std::ostringstream s;
  s << std::fixed << std::setprecision(precision) << value;
  return s.str();
}


/// Sets up a method and renders its first image (timed on top of `setupSeconds`).
std::unique_ptr<PreparedMethod> prepareMethod(const View& view, const std::string& name,
  std::shared_ptr<const BuiltScene> surfaces, std::shared_ptr<const BuiltScene> volumes,
  const sightline::RenderOptions& options, double setupSeconds, long long glyphs)
{
  auto method = std::make_unique<PreparedMethod>();
  method->result.method = name;
  method->result.primitives = glyphs;
  method->result.width = view.width;
  method->result.height = view.height;
  method->result.buildSeconds = setupSeconds;
  method->surfaces = std::move(surfaces);
  method->volumes = std::move(volumes);
  method->options = options;
  if (method->volumes)
  {
    method->options.volumes.scene = method->volumes->scene.get();
    method->options.volumes.extinction = kVolumeExtinction;
    method->options.volumes.emission = vec3(0.5f);
  }
  std::size_t bytes = method->surfaces->bytes();
  if (method->volumes)
    bytes += method->volumes->bytes();
  method->result.bytesPerPrimitive = double(bytes) / double(glyphs);
  const sightline::Camera camera = makeCamera(view);
  const double first = timeOnce([&]
    { sightline::Renderer().render(*method->surfaces->scene, camera, view.lighting, method->framebuffer, method->options); });
  method->result.firstImageSeconds = setupSeconds + first;
  return method;
}

/// `runs` timed frames of every method, round robin (each round in a rotated order), so that
/// other processes on the shared cores slow all methods alike instead of whichever ran while
/// they were busy. Fills in each method's frame timing and final image.
void timeRoundRobin(const View& view, int runs, std::vector<PreparedMethod*>& methods)
{
  const sightline::Camera camera = makeCamera(view);
  const sightline::Renderer renderer;
  for (int run = 0; run < runs; ++run)
    for (std::size_t k = 0; k < methods.size(); ++k)
    {
      PreparedMethod& m = *methods[(k + std::size_t(run)) % methods.size()];
      m.frameSeconds.push_back(timeOnce(
        [&] { renderer.render(*m.surfaces->scene, camera, view.lighting, m.framebuffer, m.options); }));
    }
  for (PreparedMethod* m : methods)
  {
    std::vector<double> seconds = m->frameSeconds;
    std::sort(seconds.begin(), seconds.end());
    FrameTiming& timing = m->result.frame;
    timing.runs = int(seconds.size());
    if (!seconds.empty())
    {
      const std::size_t n = seconds.size();
      timing.medianSeconds = n % 2 ? seconds[n / 2] : 0.5 * (seconds[n / 2 - 1] + seconds[n / 2]);
      timing.minSeconds = seconds.front();
    }
    m->result.image = imageFromFramebuffer(m->framebuffer, kGlyphBackground);
    m->framebuffer = sightline::Framebuffer();
  }
}

/// Percentage of pixels where some channel differs by more than kPixelThreshold.
double differingPixelPercent(const Image& image, const Image& reference)
{
  std::size_t differing = 0;
  for (std::size_t i = 0; i < image.pixelCount(); ++i)
    for (int c = 0; c < 3; ++c)
      if (std::abs(int(image.rgb[3 * i + c]) - int(reference.rgb[3 * i + c])) > kPixelThreshold)
      {
        ++differing;
        break;
      }
  return 100.0 * double(differing) / double(std::max<std::size_t>(1, image.pixelCount()));
}

/// Seconds per call of `work(i)` over i in [0, n): the fastest of 5 batches of at least 0.1 s
/// each (the minimum is what the code costs; other processes only ever add to it).
double secondsPerCall(std::size_t n, const std::function<void(std::size_t)>& work)
{
  if (n == 0)
    return kNotMeasured;
  double best = kNotMeasured;
  for (int batch = 0; batch < 5; ++batch)
  {
    std::size_t calls = 0;
    const auto start = std::chrono::steady_clock::now();
    double elapsed = 0.0;
    do
    {
      for (std::size_t i = 0; i < n; ++i)
        work(i);
      calls += n;
      elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    } while (elapsed < 0.1);
    const double perCall = elapsed / double(calls);
    best = std::isfinite(best) ? std::min(best, perCall) : perCall;
  }
  return best;
}
} // namespace sightline_benchmark
