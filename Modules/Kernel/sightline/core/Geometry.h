// SPDX-License-Identifier: BSD-3-Clause
// The one pattern every primitive follows: a Geometry knows its primitives' bounds, exact
// ray intersection and base colour; UserGeometry<Derived> turns that into an Embree user
// geometry with statically dispatched callbacks (no virtual call on the hot path).
#pragma once

#include "sightline/math/Math.h"
#include "sightline/core/EmbreeApi.h"
#include "sightline/core/Shading.h"
#include "sightline/core/SurfaceUnion.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace sightline
{
/// Packs an 8-bit RGBA colour the way geometries store per-primitive colours (R in the low byte).
inline std::uint32_t packRGBA8(std::uint8_t r, std::uint8_t g, std::uint8_t b, std::uint8_t a = 255)
{
  return std::uint32_t(r) | (std::uint32_t(g) << 8) | (std::uint32_t(b) << 16) | (std::uint32_t(a) << 24);
}

/// What a primitive reports at the nearest hit, in the geometry's own coordinates.
struct SurfaceHit
{
  double t = kInfinity; ///< along the double ray the primitive was given
  vec3 normal{ 0.0f }; ///< not necessarily unit length nor facing the ray
  /// The solid part hit (as InsideInterval::part), for primitives made of several parts whose
  /// colour or pick differ (a chunk of tube links); kNoPart: the primitive as a whole.
  std::uint32_t part = kNoPart;
  static constexpr std::uint32_t kNoPart = 0xffffffffu;
};

/// Abstract base of everything the renderer can trace.
class Geometry
{
public:
  virtual ~Geometry() = default;

  /// Number of primitives handed to Embree (after invalid input was dropped).
  virtual std::size_t size() const = 0;
  /// Creates and commits the Embree geometry; the caller attaches and releases it.
  virtual RTCGeometry createEmbreeGeometry(RTCDevice device) const = 0;
  /// Whether primitives carry colours of their own (scalar colouring) that replace the
  /// material's ambient and diffuse colours.
  virtual bool hasPrimitiveColors() const = 0;
  /// Colour of a primitive; only called when hasPrimitiveColors().
  virtual vec3 primitiveColor(unsigned primitive) const = 0;
  /// Colour at a surface point (scene coordinates), for primitives whose colour varies over
  /// the surface (glyphs coloured by direction). Only called when hasPrimitiveColors().
  virtual vec3 surfaceColor(unsigned primitive, const dvec3& /*point*/) const
  {
    return primitiveColor(primitive);
  }
  /// Length of the part of the ray segment [tnear, tfar] inside a primitive, for geometries
  /// rendered as homogeneous volumes (uncertainty glyphs); `entry` receives the first t inside.
  /// Geometries without an inside return 0.
  virtual double insideLength(unsigned /*primitive*/, const DoubleRay& /*ray*/, float& /*entry*/) const
  {
    return 0.0;
  }
  /// Geometries drawn as unions of solids when translucent (RenderOptions::translucent):
  /// append the intervals where the ray's whole line is inside `primitive`'s solids.
  /// The default has no inside.
  virtual void insideIntervals(unsigned /*primitive*/, const DoubleRay& /*ray*/,
    std::vector<InsideInterval>& /*out*/) const
  {
  }
  /// Outward (not necessarily unit) normal of a solid part at a point on its surface.
  virtual vec3 partNormal(std::uint32_t /*part*/, const dvec3& /*point*/) const { return vec3(0.0f); }
  /// Colour of a solid part; only called when hasPrimitiveColors().
  virtual vec3 partColor(std::uint32_t /*part*/) const { return vec3(1.0f); }
  /// Picking: what a pixel whose primary ray hit `part` of `primitive` selects (an index in
  /// [0, selectionCount())). By default the primitive; a geometry whose primitives hold
  /// several selectable elements (tube chunks: links) names the element.
  virtual std::uint32_t selectionIndex(unsigned primitive, std::uint32_t /*part*/) const
  {
    return primitive;
  }
  virtual std::size_t selectionCount() const { return size(); }
  /// Bytes the geometry itself holds (the BVH is counted by the scene).
  virtual std::size_t memoryBytes() const = 0;
  /// Whether a scene holding this geometry should build Embree's compact BVH: for sets whose
  /// BVH is a large share of their bytes (chunked tubes: 9.3 instead of 10.4 B/link, and still
  /// frames no slower, 0.88-0.91 s against 0.93-1.04 at 10^6 links). Default false.
  virtual bool prefersCompactBvh() const { return false; }
  /// Bounds of all primitives (empty box when there are none).
  virtual Box3 bounds() const = 0;

  Material material;
};

/// A double-precision ray that Embree traverses as its float rounding, with its tfar lowered to
/// each hit the primitives report. The ids of the hit that set tfar tell whether Embree's final
/// hit is that one (not a nearer one on a built-in float geometry).
struct DoubleRayTrace
{
  DoubleRay ray;
  unsigned tfarGeomID = RTC_INVALID_GEOMETRY_ID;
  unsigned tfarPrimID = RTC_INVALID_GEOMETRY_ID;
  std::uint32_t tfarPart = SurfaceHit::kNoPart; ///< the part of that hit
};

/// Embree context of every trace. In a volume or union query the user geometries do not report
/// hits: Embree then visits every box along the ray and each primitive adds the length the ray
/// spends inside it, or its inside intervals. (This is the multi-hit traversal the paper builds
/// from intersection filters; in a user geometry the intersect callback already sees every
/// candidate, so no filter function and no rtcFilterIntersection round trip is needed.)
struct TraceContext
{
  embree::QueryContext embree; ///< first member, so Embree's pointer is also ours
  bool volumeQuery = false;
  double insideLength = 0.0;
  /// Union query (translucent tubes): when set, primitives append their inside intervals to
  /// the list of the ray's id (a packet's lane; 0 for a single ray) instead of reporting hits,
  /// so Embree visits every box along the ray.
  std::vector<InsideInterval>* intervals = nullptr;
  float firstEntry = kInfinity;
  /// The double-precision rays of the trace, indexed by Embree's ray id (a packet's lane; 0 for
  /// a single ray): primitives intersect these, not Embree's float rays. Embree may regroup a
  /// packet's rays before calling back, and keeps their ids. Null when a caller traced a float
  /// ray of its own.
  DoubleRayTrace* doubleRays = nullptr;
};

/// Boxes handed to Embree are widened by this fraction of their largest coordinate (about 8 float
/// ulps): they stay conservative after rounding to float, and contain every point the double ray
/// passes within reach of Embree's float ray (which is off by ~2^-24 of its origin's distance from
/// the world origin, camera near the primitives).
constexpr double kBoxRoundingPad = 0x1p-21;

/// A box rounded outward to float and padded by kBoxRoundingPad.
inline void padForTraversal(Box3& box)
{
  for (int axis = 0; axis < 3; ++axis)
  {
    const double pad = kBoxRoundingPad *
      std::max(std::abs(double(box.lower[axis])), std::abs(double(box.upper[axis])));
    box.lower[axis] = floatAtMost(double(box.lower[axis]) - pad);
    box.upper[axis] = floatAtLeast(double(box.upper[axis]) + pad);
  }
}

/// Adapter from a primitive type to Embree's user-geometry callbacks. Derived must provide
///   Box3 bounds(unsigned primitive) const;
///   bool intersect(unsigned primitive, const DoubleRay& ray, SurfaceHit& hit) const;  // hit.t in (tnear, tfar)
/// and intersects in double, in a frame local to the primitive (ray origin minus its centre), so
/// precision depends on distances relative to the primitive, not on the distance from the origin.
template <class Derived>
class UserGeometry : public Geometry
{
public:
  RTCGeometry createEmbreeGeometry(RTCDevice device) const override
  {
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(geometry, static_cast<unsigned>(this->size()));
    rtcSetGeometryUserData(geometry, const_cast<Derived*>(static_cast<const Derived*>(this)));
    rtcSetGeometryBoundsFunction(geometry, &UserGeometry::boundsCallback, nullptr);
    rtcSetGeometryIntersectFunction(geometry, &UserGeometry::intersectCallback);
    rtcSetGeometryOccludedFunction(geometry, &UserGeometry::occludedCallback);
    rtcCommitGeometry(geometry);
    return geometry;
  }

private:
  static void boundsCallback(const RTCBoundsFunctionArguments* args)
  {
    const auto* self = static_cast<const Derived*>(args->geometryUserPtr);
    Box3 box = self->bounds(args->primID);
    padForTraversal(box);
    args->bounds_o->lower_x = box.lower.x;
    args->bounds_o->lower_y = box.lower.y;
    args->bounds_o->lower_z = box.lower.z;
    args->bounds_o->upper_x = box.upper.x;
    args->bounds_o->upper_y = box.upper.y;
    args->bounds_o->upper_z = box.upper.z;
  }

  /// The trace's double ray for this lane when it has one (no copy), else Embree's float ray
  /// in `scratch`.
  static const DoubleRay& loadRay(
    const TraceContext* trace, RTCRayN* rays, unsigned n, unsigned i, DoubleRay& scratch)
  {
    if (trace->doubleRays)
    {
      // Embree's tfar is the nearest hit so far: one of ours rounded up, or a built-in float
      // geometry's (triangles), which the double ray has not seen. Nothing beyond counts.
      DoubleRay& ray = trace->doubleRays[RTCRayN_id(rays, n, i)].ray;
      ray.tfar = std::min(ray.tfar, double(RTCRayN_tfar(rays, n, i)));
      return ray;
    }
    return scratch = DoubleRay(
      dvec3(RTCRayN_org_x(rays, n, i), RTCRayN_org_y(rays, n, i), RTCRayN_org_z(rays, n, i)),
      dvec3(RTCRayN_dir_x(rays, n, i), RTCRayN_dir_y(rays, n, i), RTCRayN_dir_z(rays, n, i)),
      RTCRayN_tnear(rays, n, i), RTCRayN_tfar(rays, n, i));
  }

  static void intersectCallback(const RTCIntersectFunctionNArguments* args)
  {
    const auto* self = static_cast<const Derived*>(args->geometryUserPtr);
    RTCRayN* rays = RTCRayHitN_RayN(args->rayhit, args->N);
    RTCHitN* hits = RTCRayHitN_HitN(args->rayhit, args->N);
    auto* trace = reinterpret_cast<TraceContext*>(args->context);
    DoubleRay scratch;
    for (unsigned i = 0; i < args->N; ++i)
    {
      if (args->valid[i] != -1)
        continue;
      if (trace->intervals)
      {
        std::vector<InsideInterval>& out = trace->intervals[RTCRayN_id(rays, args->N, i)];
        const std::size_t before = out.size();
        self->insideIntervals(args->primID, loadRay(trace, rays, args->N, i, scratch), out);
        for (std::size_t k = before; k < out.size(); ++k)
          out[k].geometry = args->geomID;
        continue;
      }
      if (trace->volumeQuery)
      {
        float entry = kInfinity;
        trace->insideLength += self->insideLength(args->primID, loadRay(trace, rays, args->N, i, scratch), entry);
        trace->firstEntry = std::min(trace->firstEntry, entry);
        continue;
      }
      SurfaceHit hit;
      if (!self->intersect(args->primID, loadRay(trace, rays, args->N, i, scratch), hit))
        continue;
      float embreeFar = float(hit.t);
      if (trace->doubleRays)
      {
        // Embree culls boxes by its float tfar: round up, so nothing before the hit is culled.
        DoubleRayTrace& lane = trace->doubleRays[RTCRayN_id(rays, args->N, i)];
        lane.ray.tfar = hit.t;
        lane.tfarGeomID = args->geomID;
        lane.tfarPrimID = args->primID;
        lane.tfarPart = hit.part;
        embreeFar = floatAtLeast(hit.t);
      }
      RTCRayN_tfar(rays, args->N, i) = embreeFar;
      RTCHitN_Ng_x(hits, args->N, i) = hit.normal.x;
      RTCHitN_Ng_y(hits, args->N, i) = hit.normal.y;
      RTCHitN_Ng_z(hits, args->N, i) = hit.normal.z;
      RTCHitN_u(hits, args->N, i) = 0.0f;
      RTCHitN_v(hits, args->N, i) = 0.0f;
      RTCHitN_primID(hits, args->N, i) = args->primID;
      RTCHitN_geomID(hits, args->N, i) = args->geomID;
      embree::copyInstance(hits, args->N, i, *args->context);
    }
  }

  static void occludedCallback(const RTCOccludedFunctionNArguments* args)
  {
    const auto* self = static_cast<const Derived*>(args->geometryUserPtr);
    const auto* trace = reinterpret_cast<const TraceContext*>(args->context);
    DoubleRay scratch;
    for (unsigned i = 0; i < args->N; ++i)
    {
      if (args->valid[i] != -1)
        continue;
      SurfaceHit hit;
      if (self->intersect(args->primID, loadRay(trace, args->ray, args->N, i, scratch), hit))
        RTCRayN_tfar(args->ray, args->N, i) = -kInfinity;
    }
  }
};

/// Input problems a geometry found and skipped; the VTK layer turns these into warnings.
struct ValidationReport
{
  std::size_t rejected = 0;         ///< primitives dropped
  std::vector<std::string> reasons; ///< one line per kind of problem, naming the first index
  bool clean() const { return rejected == 0; }
};
} // namespace sightline
