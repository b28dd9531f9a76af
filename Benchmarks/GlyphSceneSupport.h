// SPDX-License-Identifier: BSD-3-Clause
// What the glyph scenes (sh-glyphs, tensor-glyphs, and in part sh-glyph-window) share: a slice of glyphs seen from above at
// a tilt, one light, the glyph material, Embree scenes built per method, methods prepared and
// then timed round robin, and the pixel and per-call measures their tables report.
#pragma once

#include "BenchmarkSupport.h"

#include "sightline/core/Camera.h"
#include "sightline/core/EmbreeScene.h"
#include "sightline/core/Framebuffer.h"
#include "sightline/core/Renderer.h"
#include "sightline/core/Shading.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace sightline_benchmark
{
/// Background of every glyph image.
const double kGlyphBackground[3] = { 0.1, 0.1, 0.12 };
/// The camera looks down at the slice, tilted this far (degrees) about the slice's x axis.
constexpr double kTiltDegrees = 20.0;
/// Uncertainty volumes: extinction per unit length (grey emission 0.5).
constexpr float kVolumeExtinction = 3.0f;
/// A pixel "differs" when a channel differs by more than this (0-255).
constexpr int kPixelThreshold = 8;

/// Camera and light shared by every method of a data set.
struct View
{
  sightline::CameraParameters parameters;
  sightline::Lighting lighting;
  int width = 0;
  int height = 0;
};

/// The nearest tilted view that frames every glyph centre (plus `glyphRadius`), with one
/// directional light from the upper left so that shadows fall visibly.
View makeGlyphView(const std::vector<sightline::vec3>& centers, double glyphRadius, int width, int height);
sightline::Camera makeCamera(const View& view);
/// A glTF dielectric, roughness 0.45.
sightline::Material glyphMaterial();

/// A committed scene with its own Embree device (so that its memory monitor sees only it);
/// empty when the geometry is null.
struct BuiltScene
{
  std::shared_ptr<sightline::EmbreeDevice> device = std::make_shared<sightline::EmbreeDevice>();
  std::unique_ptr<sightline::EmbreeScene> scene;

  explicit BuiltScene(std::shared_ptr<const sightline::Geometry> geometry);
  std::size_t bytes() const { return scene->geometryBytes() + std::size_t(scene->bvhBytes()); }
};

/// `value` with `precision` digits after the point; "-" when it is not finite.
std::string fixed(double value, int precision);

/// One method, built and rendered once, ready for timed frames: a surface scene, optionally
/// a volume scene, render options, and the row it fills in.
struct PreparedMethod
{
  MethodResult result;
  std::shared_ptr<const BuiltScene> surfaces;
  std::shared_ptr<const BuiltScene> volumes;
  sightline::RenderOptions options;
  sightline::Framebuffer framebuffer;
  std::vector<double> frameSeconds;
};

/// Sets up a method and renders its first image (timed on top of `setupSeconds`).
std::unique_ptr<PreparedMethod> prepareMethod(const View& view, const std::string& name,
  std::shared_ptr<const BuiltScene> surfaces, std::shared_ptr<const BuiltScene> volumes,
  const sightline::RenderOptions& options, double setupSeconds, long long glyphs);

/// `runs` timed frames of every method, round robin (each round in a rotated order), so that
/// other processes on the shared cores slow all methods alike instead of whichever ran while
/// they were busy. Fills in each method's frame timing and final image.
void timeRoundRobin(const View& view, int runs, std::vector<PreparedMethod*>& methods);

/// Percentage of pixels where some channel differs by more than kPixelThreshold.
double differingPixelPercent(const Image& image, const Image& reference);

/// Seconds per call of `work(i)` over i in [0, n): the fastest of 5 batches of at least 0.1 s
/// each (the minimum is what the code costs; other processes only ever add to it).
double secondsPerCall(std::size_t n, const std::function<void(std::size_t)>& work);
} // namespace sightline_benchmark
