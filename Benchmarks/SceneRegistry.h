// SPDX-License-Identifier: BSD-3-Clause
// Named benchmark scenes. A scene registers a name and a function that renders it with every
// method it knows (one of them the reference) for a given primitive count; the harness does
// the rest (errors against the reference, images, CSV, table, plot). To add a scene, define
// in a new source file of this directory:
//
//   static const sightline_benchmark::SceneRegistration registration{ "tubes",
//     "what it shows", { 100000 }, &RunTubeScene };
#pragma once

#include "BenchmarkSupport.h"

#include <functional>
#include <string>
#include <vector>

namespace sightline_benchmark
{
/// Renders a scene of `count` primitives with every method. `machine` receives the OpenGL
/// description when the scene opens a window.
using SceneFunction = std::function<std::vector<MethodResult>(
  const Options& options, long long count, MachineDescription& machine)>;

struct Scene
{
  std::string name;
  std::string description;
  std::vector<long long> defaultCounts;
  SceneFunction run;
};

class SceneRegistry
{
public:
  static SceneRegistry& instance();
  void add(Scene scene);
  /// nullptr when no scene has this name.
  const Scene* find(const std::string& name) const;
  /// Scenes sorted by name.
  std::vector<const Scene*> scenes() const;

private:
  std::vector<Scene> Scenes;
};

/// Registers a scene during static initialisation (define one at namespace scope).
struct SceneRegistration
{
  SceneRegistration(std::string name, std::string description, std::vector<long long> defaultCounts,
    SceneFunction run);
};
} // namespace sightline_benchmark
