// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/core/EmbreeScene.h"

#include <algorithm>
#include <chrono>
#if defined(__SSE2__)
#include <immintrin.h>
#endif
#include <mutex>
#include <stdexcept>
#include <string>

namespace sightline
{
namespace
{
const char* errorName(RTCError error)
{
  switch (error)
  {
    case RTC_ERROR_NONE: return "no error";
    case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
    case RTC_ERROR_CANCELLED: return "cancelled";
    default: return "unknown error";
  }
}
} // namespace

EmbreeDevice::EmbreeDevice()
{
  Device = rtcNewDevice(nullptr);
  if (!Device)
    throw std::runtime_error(std::string("sightline: could not create an Embree device: ") +
      errorName(rtcGetDeviceError(nullptr)));
  rtcSetDeviceMemoryMonitorFunction(Device, &EmbreeDevice::memoryMonitor, this);
  // Larger packets than the machine's vectors are split by Embree's stream code: no gain.
  if (rtcGetDeviceProperty(Device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED))
    PacketSize = 16;
  else if (rtcGetDeviceProperty(Device, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED))
    PacketSize = 8;
  else if (rtcGetDeviceProperty(Device, RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED))
    PacketSize = 4;
}

EmbreeDevice::~EmbreeDevice()
{
  rtcReleaseDevice(Device);
}

bool EmbreeDevice::memoryMonitor(void* user, std::ptrdiff_t bytes, bool /*post*/)
{
  static_cast<EmbreeDevice*>(user)->Allocated += bytes;
  return true;
}

void EmbreeDevice::throwOnError(const char* what) const
{
  const RTCError error = rtcGetDeviceError(Device);
  if (error != RTC_ERROR_NONE)
    throw std::runtime_error(std::string("sightline: Embree failed in ") + what + ": " +
      errorName(error));
}

std::shared_ptr<EmbreeDevice> EmbreeDevice::shared()
{
  static std::mutex mutex;
  static std::weak_ptr<EmbreeDevice> instance;
  std::lock_guard<std::mutex> lock(mutex);
  std::shared_ptr<EmbreeDevice> device = instance.lock();
  if (!device)
  {
    device = std::make_shared<EmbreeDevice>();
    instance = device;
  }
  return device;
}

EmbreeScene::EmbreeScene(std::shared_ptr<EmbreeDevice> device)
  : Device(std::move(device))
{
  Scene = rtcNewScene(Device->handle());
  Device->throwOnError("rtcNewScene");
  rtcSetSceneBuildQuality(Scene, RTC_BUILD_QUALITY_HIGH);
}

EmbreeScene::~EmbreeScene()
{
  rtcReleaseScene(Scene);
}

unsigned EmbreeScene::add(std::shared_ptr<const Geometry> geometry)
{
  if (!geometry)
    throw std::invalid_argument("sightline::EmbreeScene::add: null geometry");
  if (Committed)
    throw std::logic_error("sightline::EmbreeScene::add: the scene is already committed");
  RTCGeometry handle = geometry->createEmbreeGeometry(Device->handle());
  Device->throwOnError("creating a geometry");
  const unsigned id = rtcAttachGeometry(Scene, handle);
  rtcReleaseGeometry(handle);
  Device->throwOnError("rtcAttachGeometry");
  if (id != Geometries.size())
    throw std::logic_error("sightline::EmbreeScene: unexpected geometry id");
  Geometries.push_back(std::move(geometry));
  return id;
}

void EmbreeScene::commit()
{
  const bool compact = std::any_of(Geometries.begin(), Geometries.end(),
    [](const std::shared_ptr<const Geometry>& g) { return g->prefersCompactBvh(); });
  if (compact)
    rtcSetSceneFlags(Scene, RTC_SCENE_FLAG_COMPACT);
  const std::int64_t before = Device->allocatedBytes();
  const auto start = std::chrono::steady_clock::now();
  rtcCommitScene(Scene);
  BuildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  Device->throwOnError("rtcCommitScene");
  BvhBytes = Device->allocatedBytes() - before;
  Committed = true;
}

Box3 EmbreeScene::bounds() const
{
  RTCBounds b;
  rtcGetSceneBounds(Scene, &b);
  Box3 box;
  if (Geometries.empty())
    return box;
  box.lower = vec3(b.lower_x, b.lower_y, b.lower_z);
  box.upper = vec3(b.upper_x, b.upper_y, b.upper_z);
  return box;
}

std::size_t EmbreeScene::geometryBytes() const
{
  std::size_t bytes = 0;
  for (const auto& g : Geometries)
    bytes += g->memoryBytes();
  return bytes;
}

namespace
{
/// Whether Embree accepts the float ray (its RayK::valid(): finite origin and direction within
/// +-1.844e18, tnear and tfar not NaN). Data placed absurdly far away (a corrupt NIfTI affine)
/// gives rays beyond that; they are traced as disabled rays and miss, instead of tripping
/// Embree's assertion, which aborts the process.
inline bool embreeAccepts(const Ray& ray)
{
  constexpr float kLargest = 1.844e18f; // Embree's FLT_LARGE
  for (int i = 0; i < 3; ++i)
  {
    if (!(std::abs(ray.origin[i]) <= kLargest) || !(std::abs(ray.direction[i]) <= kLargest))
    {
      return false;
    }
  }
  return !std::isnan(ray.tnear) && !std::isnan(ray.tfar);
}

/// A ray Embree skips (tnear > tfar, mask 0): traced, it hits nothing.
inline Ray disabledRay()
{
  Ray ray;
  ray.origin = vec3(0.0f);
  ray.direction = vec3(0.0f, 0.0f, 1.0f);
  ray.tnear = 1.0f;
  ray.tfar = 0.0f;
  return ray;
}

inline void fillEmbreeRay(RTCRay& out, const Ray& given)
{
  const Ray ray = embreeAccepts(given) ? given : disabledRay();
#if defined(__SSE2__)
  // Embree loads (org, tnear) and (dir, time) as one 16-byte vector each, right after this
  // returns: written as single 16-byte stores they forward to those loads; eight scalar stores
  // cannot, and each trace would wait for them to reach the cache.
  _mm_storeu_ps(&out.org_x, _mm_setr_ps(ray.origin.x, ray.origin.y, ray.origin.z, ray.tnear));
  _mm_storeu_ps(&out.dir_x, _mm_setr_ps(ray.direction.x, ray.direction.y, ray.direction.z, 0.0f));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(&out.tfar),
    _mm_setr_epi32(_mm_cvtsi128_si32(_mm_castps_si128(_mm_set_ss(ray.tfar))), -1, 0, 0));
#else
  out.org_x = ray.origin.x;
  out.org_y = ray.origin.y;
  out.org_z = ray.origin.z;
  out.tnear = ray.tnear;
  out.dir_x = ray.direction.x;
  out.dir_y = ray.direction.y;
  out.dir_z = ray.direction.z;
  out.time = 0.0f;
  out.tfar = ray.tfar;
  out.mask = ~0u;
  out.id = 0;
  out.flags = 0;
#endif
}
} // namespace

RTCRayHit makeRayHit(const Ray& ray)
{
  RTCRayHit rh;
  fillEmbreeRay(rh.ray, ray);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

bool EmbreeScene::intersect(RTCRayHit& rayhit, bool coherent) const
{
  TraceContext context;
  embree::initContext(context.embree);
  embree::intersect1(Scene, context.embree, rayhit, coherent);
  return rayhit.hit.geomID != RTC_INVALID_GEOMETRY_ID;
}

namespace
{
/// A context whose primitives intersect `trace.ray` while Embree traverses its float rounding.
void initDoubleTrace(TraceContext& context, DoubleRayTrace& trace, const DoubleRay& ray)
{
  embree::initContext(context.embree);
  trace.ray = ray;
  context.doubleRays = &trace;
}

/// The nearest hit Embree found for a double ray: the double t its primitive reported, or
/// Embree's float t when a built-in float geometry was nearer.
void readHit(const DoubleRayTrace& trace, unsigned geomID, unsigned primID, float embreeFar,
  const vec3& normal, SceneHit& hit)
{
  const bool userHit = geomID == trace.tfarGeomID && primID == trace.tfarPrimID;
  hit.t = userHit ? trace.ray.tfar : double(embreeFar);
  hit.normal = normal;
  hit.geomID = geomID;
  hit.primID = primID;
  hit.part = userHit ? trace.tfarPart : SurfaceHit::kNoPart;
}

void intersectNative(const int* valid, RTCScene scene, embree::QueryContext& context,
  RTCRayHitNt<4>& rh, bool coherent)
{
  embree::intersect4(valid, scene, context, reinterpret_cast<RTCRayHit4&>(rh), coherent);
}
void intersectNative(const int* valid, RTCScene scene, embree::QueryContext& context,
  RTCRayHitNt<8>& rh, bool coherent)
{
  embree::intersect8(valid, scene, context, reinterpret_cast<RTCRayHit8&>(rh), coherent);
}
void intersectNative(const int* valid, RTCScene scene, embree::QueryContext& context,
  RTCRayHitNt<16>& rh, bool coherent)
{
  embree::intersect16(valid, scene, context, reinterpret_cast<RTCRayHit16&>(rh), coherent);
}

/// Fills lanes [0, count) of a K-wide packet with the float rounding of the active rays (ray id
/// = lane) and their double rays; the other lanes are invalid, and also disabled rays
/// (tnear > tfar, mask 0): a packet wider than the CPU's (16 rays without AVX-512) goes through
/// Embree's ray stream code, which ignores the valid mask and skips only such rays.
template <int K>
void fillPacket(RTCRayHitNt<K>& rh, int* valid, DoubleRayTrace* traces, const DoubleRay* rays,
  const bool* active, int count)
{
  for (int i = 0; i < K; ++i)
  {
    valid[i] = i < count && active[i] ? -1 : 0;
    if (!valid[i])
    {
      rh.ray.org_x[i] = rh.ray.org_y[i] = rh.ray.org_z[i] = 0.0f;
      rh.ray.dir_x[i] = rh.ray.dir_y[i] = 0.0f;
      rh.ray.dir_z[i] = 1.0f;
      rh.ray.tnear[i] = 1.0f;
      rh.ray.tfar[i] = 0.0f;
      rh.ray.time[i] = 0.0f;
      rh.ray.mask[i] = 0u;
      rh.ray.id[i] = unsigned(i);
      rh.ray.flags[i] = 0;
      rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
      continue;
    }
    traces[i].ray = rays[i];
    const Ray rounded = rays[i].rounded();
    const Ray ray = embreeAccepts(rounded) ? rounded : disabledRay();
    rh.ray.org_x[i] = ray.origin.x;
    rh.ray.org_y[i] = ray.origin.y;
    rh.ray.org_z[i] = ray.origin.z;
    rh.ray.tnear[i] = ray.tnear;
    rh.ray.dir_x[i] = ray.direction.x;
    rh.ray.dir_y[i] = ray.direction.y;
    rh.ray.dir_z[i] = ray.direction.z;
    rh.ray.time[i] = 0.0f;
    rh.ray.tfar[i] = ray.tfar;
    rh.ray.mask[i] = ~0u;
    rh.ray.id[i] = unsigned(i);
    rh.ray.flags[i] = 0;
    rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID[i] = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
  }
}

/// One K-wide packet of rays[0, count) with its double rays in a trace context.
template <int K>
struct PacketTrace
{
  alignas(64) RTCRayHitNt<K> rh;
  alignas(64) int valid[K];
  DoubleRayTrace traces[K];
  TraceContext context;

  PacketTrace(const DoubleRay* rays, const bool* active, int count)
  {
    fillPacket<K>(rh, valid, traces, rays, active, count);
    embree::initContext(context.embree);
    context.doubleRays = traces;
  }
  void trace(RTCScene scene, bool coherent) { intersectNative(valid, scene, context.embree, rh, coherent); }
};

/// Traces rays[0, count) (count <= K) as one Embree packet of K lanes for their nearest hits.
template <int K>
void intersectPacketOf(RTCScene scene, const DoubleRay* rays, const bool* active, int count,
  SceneHit* hits, bool* found, bool coherent)
{
  PacketTrace<K> packet(rays, active, count);
  packet.trace(scene, coherent);
  const RTCRayHitNt<K>& rh = packet.rh;
  for (int i = 0; i < count; ++i)
  {
    found[i] = packet.valid[i] && rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;
    if (found[i])
      readHit(packet.traces[i], rh.hit.geomID[i], rh.hit.primID[i], rh.ray.tfar[i],
        vec3(rh.hit.Ng_x[i], rh.hit.Ng_y[i], rh.hit.Ng_z[i]), hits[i]);
  }
}

/// Traces rays[0, count) (count <= K) as one packet collecting each lane's inside intervals.
template <int K>
void insideIntervalsPacketOf(RTCScene scene, const DoubleRay* rays, const bool* active, int count,
  std::vector<InsideInterval>* out)
{
  PacketTrace<K> packet(rays, active, count);
  packet.context.intervals = out;
  packet.trace(scene, false);
}

/// Checks a packet's ray count.
void checkPacketCount(const char* what, int count)
{
  if (count < 1 || count > EmbreeScene::kMaxPacket)
    throw std::invalid_argument(std::string("sightline::EmbreeScene::") + what + ": " +
      std::to_string(count) + " rays, expected 1 to " + std::to_string(EmbreeScene::kMaxPacket));
}
} // namespace

bool EmbreeScene::intersect(const DoubleRay& ray, SceneHit& hit, bool coherent) const
{
  RTCRayHit rh;
  fillEmbreeRay(rh.ray, ray.rounded());
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  TraceContext context;
  DoubleRayTrace trace;
  initDoubleTrace(context, trace, ray);
  embree::intersect1(Scene, context.embree, rh, coherent);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID)
    return false;
  readHit(trace, rh.hit.geomID, rh.hit.primID, rh.ray.tfar, vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z), hit);
  return true;
}

void EmbreeScene::intersectPacket(const DoubleRay* rays, const bool* active, int count,
  SceneHit* hits, bool* found, bool coherent) const
{
  checkPacketCount("intersectPacket", count);
  if (count == 1)
    found[0] = active[0] && intersect(rays[0], hits[0], coherent);
  else if (count <= 4)
    intersectPacketOf<4>(Scene, rays, active, count, hits, found, coherent);
  else if (count <= 8)
    intersectPacketOf<8>(Scene, rays, active, count, hits, found, coherent);
  else
    intersectPacketOf<16>(Scene, rays, active, count, hits, found, coherent);
}

bool EmbreeScene::occluded(const DoubleRay& ray) const
{
  RTCRayHit rh = makeRayHit(ray.rounded());
  TraceContext context;
  DoubleRayTrace trace;
  initDoubleTrace(context, trace, ray);
  embree::occluded1(Scene, context.embree, rh.ray);
  return rh.ray.tfar < 0.0f;
}

double EmbreeScene::insideLength(const DoubleRay& ray, float& firstEntry) const
{
  RTCRayHit rh = makeRayHit(ray.rounded());
  TraceContext context;
  DoubleRayTrace trace;
  initDoubleTrace(context, trace, ray);
  context.volumeQuery = true;
  embree::intersect1(Scene, context.embree, rh, false);
  firstEntry = context.firstEntry;
  return context.insideLength;
}

void EmbreeScene::insideIntervals(const DoubleRay& ray, std::vector<InsideInterval>& out) const
{
  RTCRayHit rh = makeRayHit(ray.rounded());
  TraceContext context;
  DoubleRayTrace trace;
  initDoubleTrace(context, trace, ray);
  context.intervals = &out;
  embree::intersect1(Scene, context.embree, rh, false);
}

void EmbreeScene::insideIntervalsPacket(const DoubleRay* rays, const bool* active, int count,
  std::vector<InsideInterval>* out) const
{
  checkPacketCount("insideIntervalsPacket", count);
  if (count == 1)
  {
    if (active[0])
      insideIntervals(rays[0], out[0]);
  }
  else if (count <= 4)
    insideIntervalsPacketOf<4>(Scene, rays, active, count, out);
  else if (count <= 8)
    insideIntervalsPacketOf<8>(Scene, rays, active, count, out);
  else
    insideIntervalsPacketOf<16>(Scene, rays, active, count, out);
}
} // namespace sightline
