// SPDX-License-Identifier: BSD-3-Clause
// RAII ownership of an Embree device and scene, plus the bookkeeping benchmarks need
// (BVH build time and bytes).
#pragma once

#include "sightline/core/EmbreeApi.h"
#include "sightline/core/Geometry.h"

#include <atomic>
#include <memory>
#include <vector>

namespace sightline
{
/// One Embree device. Errors reported by Embree are turned into std::runtime_error when the
/// failing call returns. Track memory to measure BVH sizes.
class EmbreeDevice
{
public:
  EmbreeDevice();
  ~EmbreeDevice();
  EmbreeDevice(const EmbreeDevice&) = delete;
  EmbreeDevice& operator=(const EmbreeDevice&) = delete;

  RTCDevice handle() const { return Device; }
  /// Bytes Embree currently holds (BVHs and their builders' scratch freed after the build).
  std::int64_t allocatedBytes() const { return Allocated.load(); }
  /// Rays per packet Embree traces natively here (16 with AVX-512, 8 with AVX, 4 with SSE; 1
  /// when built without packet support): the packet size the renderer gives intersectPacket.
  int packetSize() const { return PacketSize; }
  /// Throws std::runtime_error if Embree recorded an error since the last check.
  void throwOnError(const char* what) const;

  /// A device shared by everything in the process that does not need its own.
  static std::shared_ptr<EmbreeDevice> shared();

private:
  static bool memoryMonitor(void* user, std::ptrdiff_t bytes, bool post);
  RTCDevice Device = nullptr;
  std::atomic<std::int64_t> Allocated{ 0 };
  int PacketSize = 1;
};

/// The nearest hit of a double-precision ray.
struct SceneHit
{
  double t = kInfinity; ///< along the double ray
  vec3 normal{ 0.0f };  ///< the primitive's (not necessarily unit, nor facing the ray)
  unsigned geomID = RTC_INVALID_GEOMETRY_ID;
  unsigned primID = RTC_INVALID_GEOMETRY_ID;
  std::uint32_t part = SurfaceHit::kNoPart; ///< the part of the primitive hit (SurfaceHit::part)
};

/// Geometries plus their BVH. Add geometries, commit, then trace from any number of threads.
class EmbreeScene
{
public:
  explicit EmbreeScene(std::shared_ptr<EmbreeDevice> device = EmbreeDevice::shared());
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  /// Adds a geometry (kept alive by the scene); returns its Embree geometry id.
  unsigned add(std::shared_ptr<const Geometry> geometry);
  /// Builds the BVH. Must be called after the last add() and before tracing.
  void commit();

  bool empty() const { return Geometries.empty(); }
  const EmbreeDevice& device() const { return *Device; }
  const Geometry& geometry(unsigned geomID) const { return *Geometries[geomID]; }
  RTCScene handle() const { return Scene; }
  Box3 bounds() const;

  double buildSeconds() const { return BuildSeconds; }
  /// Bytes of the BVH (measured through the device's memory monitor around the build).
  std::int64_t bvhBytes() const { return BvhBytes; }
  /// Bytes of the geometries' own data.
  std::size_t geometryBytes() const;

  /// Nearest hit along the ray; true if something was hit. Embree traverses the float rounding
  /// of the ray, the primitives intersect the double ray itself.
  bool intersect(const DoubleRay& ray, SceneHit& hit, bool coherent = false) const;
  /// The most rays intersectPacket takes.
  static constexpr int kMaxPacket = 16;
  /// Nearest hits of rays[0, count) traced together as one Embree packet (count <= kMaxPacket,
  /// best device().packetSize()): coherent rays, such as a tile's primary rays, share the BVH
  /// nodes they visit. found[i] tells whether rays[i] hit (then hits[i] is set); rays whose
  /// `active` is false are not traced. Each ray gets the hit intersect() would give it.
  void intersectPacket(const DoubleRay* rays, const bool* active, int count, SceneHit* hits,
    bool* found, bool coherent = true) const;
  /// The same for a float ray given as Embree's (rayhit.hit and rayhit.ray.tfar filled in).
  bool intersect(RTCRayHit& rayhit, bool coherent = false) const;
  /// Whether anything lies on the ray in [tnear, tfar].
  bool occluded(const DoubleRay& ray) const;
  /// Total length of the ray segment [tnear, tfar] inside the scene's volume primitives
  /// (see Geometry::insideLength); `firstEntry` receives where the ray first enters one.
  double insideLength(const DoubleRay& ray, float& firstEntry) const;

  /// Appends the inside intervals (Geometry::insideIntervals) of every primitive whose box the
  /// ray segment [tnear, tfar] crosses; the intervals themselves are not clipped.
  void insideIntervals(const DoubleRay& ray, std::vector<InsideInterval>& out) const;
  /// The same for rays[0, count) traced together as one packet (count <= kMaxPacket): ray i's
  /// intervals are appended to out[i]; rays whose `active` is false are not traced.
  void insideIntervalsPacket(const DoubleRay* rays, const bool* active, int count,
    std::vector<InsideInterval>* out) const;

private:
  std::shared_ptr<EmbreeDevice> Device;
  RTCScene Scene = nullptr;
  std::vector<std::shared_ptr<const Geometry>> Geometries;
  double BuildSeconds = 0.0;
  std::int64_t BvhBytes = 0;
  bool Committed = false;
};

/// Fills an Embree ray from ours.
RTCRayHit makeRayHit(const Ray& ray);
} // namespace sightline
