// SPDX-License-Identifier: BSD-3-Clause
#include "SceneRegistry.h"

#include <algorithm>
#include <stdexcept>

namespace sightline_benchmark
{
SceneRegistry& SceneRegistry::instance()
{
  // A function-local static is constructed on first use, so registrations in other
  // translation units may run in any order.
  static SceneRegistry registry;
  return registry;
}

void SceneRegistry::add(Scene scene)
{
  if (this->find(scene.name))
  {
    throw std::logic_error("benchmark scene '" + scene.name + "' is registered twice");
  }
  this->Scenes.push_back(std::move(scene));
}

const Scene* SceneRegistry::find(const std::string& name) const
{
  for (const Scene& scene : this->Scenes)
  {
    if (scene.name == name)
    {
      return &scene;
    }
  }
  return nullptr;
}

std::vector<const Scene*> SceneRegistry::scenes() const
{
  std::vector<const Scene*> sorted;
  for (const Scene& scene : this->Scenes)
  {
    sorted.push_back(&scene);
  }
  std::sort(
    sorted.begin(), sorted.end(), [](const Scene* a, const Scene* b) { return a->name < b->name; });
  return sorted;
}

SceneRegistration::SceneRegistration(std::string name, std::string description,
  std::vector<long long> defaultCounts, SceneFunction run)
{
  SceneRegistry::instance().add(
    { std::move(name), std::move(description), std::move(defaultCounts), std::move(run) });
}
} // namespace sightline_benchmark
