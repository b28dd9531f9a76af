// SPDX-License-Identifier: BSD-3-Clause
// The one place where Embree 3.13 and Embree 4 differ for Sightline. Everything else uses
// Embree's types and calls that are the same in both (devices, scenes, geometries, RTCRayHit,
// the RTCRayN/RTCHitN accessors) and, for what changed, the functions here:
// - Embree 4 renamed the intersection context RTCIntersectContext to RTCRayQueryContext and
//   moved it, with the coherent flag, into RTCIntersectArguments / RTCOccludedArguments,
//   passed last to rtcIntersect* and rtcOccluded*;
// - Embree 4 built with instance arrays (Debian's 4.3.3 is) has a hit field instPrimID that a
//   user geometry fills from the context as it fills instID.
// CMake defines SIGHTLINE_EMBREE_MAJOR (3 or 4) from the Embree it found, publicly, so code
// built against an installed Sightline sees the same headers.
#pragma once

#if SIGHTLINE_EMBREE_MAJOR >= 4
#include <embree4/rtcore.h>
#elif SIGHTLINE_EMBREE_MAJOR == 3
#include <embree3/rtcore.h>
#else
#error "SIGHTLINE_EMBREE_MAJOR must be 3 or 4 (link Sightline::Kernel, which defines it)"
#endif

namespace sightline
{
namespace embree
{
#if SIGHTLINE_EMBREE_MAJOR >= 4
/// The context every trace carries to the user geometries' callbacks.
using QueryContext = RTCRayQueryContext;

inline void initContext(QueryContext& context)
{
  rtcInitRayQueryContext(&context);
}

/// rtcIntersect's arguments: `context`, and whether the rays are coherent (a tile's primary rays).
inline RTCIntersectArguments intersectArguments(QueryContext& context, bool coherent)
{
  RTCIntersectArguments args;
  rtcInitIntersectArguments(&args);
  args.context = &context;
  args.flags = coherent ? RTC_RAY_QUERY_FLAG_COHERENT : RTC_RAY_QUERY_FLAG_INCOHERENT;
  return args;
}

inline void intersect1(RTCScene scene, QueryContext& context, RTCRayHit& rayhit, bool coherent)
{
  RTCIntersectArguments args = intersectArguments(context, coherent);
  rtcIntersect1(scene, &rayhit, &args);
}
inline void intersect4(const int* valid, RTCScene scene, QueryContext& context, RTCRayHit4& rayhit, bool coherent)
{
  RTCIntersectArguments args = intersectArguments(context, coherent);
  rtcIntersect4(valid, scene, &rayhit, &args);
}
inline void intersect8(const int* valid, RTCScene scene, QueryContext& context, RTCRayHit8& rayhit, bool coherent)
{
  RTCIntersectArguments args = intersectArguments(context, coherent);
  rtcIntersect8(valid, scene, &rayhit, &args);
}
inline void intersect16(const int* valid, RTCScene scene, QueryContext& context, RTCRayHit16& rayhit, bool coherent)
{
  RTCIntersectArguments args = intersectArguments(context, coherent);
  rtcIntersect16(valid, scene, &rayhit, &args);
}
inline void occluded1(RTCScene scene, QueryContext& context, RTCRay& ray)
{
  RTCOccludedArguments args;
  rtcInitOccludedArguments(&args);
  args.context = &context;
  rtcOccluded1(scene, &ray, &args);
}
#else
using QueryContext = RTCIntersectContext;

inline void initContext(QueryContext& context)
{
  rtcInitIntersectContext(&context);
}

/// Embree 3 keeps the coherent flag in the context itself.
inline QueryContext& flagged(QueryContext& context, bool coherent)
{
  context.flags = coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  return context;
}

inline void intersect1(RTCScene scene, QueryContext& context, RTCRayHit& rayhit, bool coherent)
{
  rtcIntersect1(scene, &flagged(context, coherent), &rayhit);
}
inline void intersect4(const int* valid, RTCScene scene, QueryContext& context, RTCRayHit4& rayhit, bool coherent)
{
  rtcIntersect4(valid, scene, &flagged(context, coherent), &rayhit);
}
inline void intersect8(const int* valid, RTCScene scene, QueryContext& context, RTCRayHit8& rayhit, bool coherent)
{
  rtcIntersect8(valid, scene, &flagged(context, coherent), &rayhit);
}
inline void intersect16(const int* valid, RTCScene scene, QueryContext& context, RTCRayHit16& rayhit, bool coherent)
{
  rtcIntersect16(valid, scene, &flagged(context, coherent), &rayhit);
}
inline void occluded1(RTCScene scene, QueryContext& context, RTCRay& ray)
{
  rtcOccluded1(scene, &context, &ray);
}
#endif

/// A user geometry's hit names the instance it was found in, as the context says.
inline void copyInstance(RTCHitN* hits, unsigned n, unsigned i, const QueryContext& context)
{
  RTCHitN_instID(hits, n, i, 0) = context.instID[0];
#if defined(RTC_GEOMETRY_INSTANCE_ARRAY)
  RTCHitN_instPrimID(hits, n, i, 0) = context.instPrimID[0];
#endif
}
} // namespace embree
} // namespace sightline
