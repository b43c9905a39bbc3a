// The rays scene on Embree 3: one triangle geometry in a scene built at
// RTC_BUILD_QUALITY_HIGH on a device limited to one thread, cast with rtcIntersect1, in
// packets of 16 (rtcIntersect16) and as one stream (rtcIntersect1M). Rays are given the
// same unnormalised direction and tfar = 1, so the hit's tfar is the fraction pfx reports.
#include <embree3/rtcore.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_rays.h"

namespace pfxbench {

namespace {

// Bytes the device holds now: allocations count up, frees down.
bool trackDeviceMemory(void* userPtr, ssize_t bytes, bool) {
  *static_cast<double*>(userPtr) += double(bytes);
  return true;
}

// Owns the handles, so that a failure half way releases what was made.
struct EmbreeHandles {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~EmbreeHandles() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

bool deviceFailed(RTCDevice device, const char* what, std::string& error) {
  const RTCError code = rtcGetDeviceError(device);
  if (code == RTC_ERROR_NONE) return false;
  error = std::string(what) + " failed with Embree error " + std::to_string(int(code));
  return true;
}

double distanceOf(unsigned geomID, float tfar, double length) {
  return geomID != RTC_INVALID_GEOMETRY_ID ? double(tfar) * length : kRayMiss;
}

void setRay(const RaySet& rays, std::size_t i, RTCRayHit& rayHit) {
  RTCRay& ray = rayHit.ray;
  ray.org_x = rays.starts[3 * i];
  ray.org_y = rays.starts[3 * i + 1];
  ray.org_z = rays.starts[3 * i + 2];
  ray.dir_x = rays.directions[3 * i];
  ray.dir_y = rays.directions[3 * i + 1];
  ray.dir_z = rays.directions[3 * i + 2];
  ray.tnear = 0;
  ray.tfar = 1;
  ray.time = 0;
  ray.mask = ~0u;
  ray.id = unsigned(i);
  ray.flags = 0;
  rayHit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rayHit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

}  // namespace

bool runEmbreeRays(const RayTerrain& terrain, const RaySet& rays, RayEngineFigures& figures,
                   std::string& error) {
  EmbreeHandles handles;
  handles.device = rtcNewDevice("threads=1");
  if (!handles.device) {
    error = "rtcNewDevice failed";
    return false;
  }
  double deviceBytes = 0;
  rtcSetDeviceMemoryMonitorFunction(handles.device, trackDeviceMemory, &deviceBytes);

  const double bytesBefore = deviceBytes;
  const double cpuStart = processCpuSeconds();
  const auto start = std::chrono::steady_clock::now();
  handles.scene = rtcNewScene(handles.device);
  rtcSetSceneBuildQuality(handles.scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry geometry = rtcNewGeometry(handles.device, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_HIGH);
  auto* vertices = static_cast<float*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                              3 * sizeof(float), terrain.numVertices()));
  auto* indices = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                              3 * sizeof(unsigned), terrain.numTriangles()));
  if (!vertices || !indices) {
    rtcReleaseGeometry(geometry);
    deviceFailed(handles.device, "rtcSetNewGeometryBuffer", error);
    return false;
  }
  std::copy(terrain.vertices.begin(), terrain.vertices.end(), vertices);
  std::copy(terrain.triangles.begin(), terrain.triangles.end(), indices);
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(handles.scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(handles.scene);
  RayBuildFigures build{"embree", "high_quality", 0, 0};
  build.buildSeconds = processCpuSeconds() - cpuStart;
  const double wallSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (deviceFailed(handles.device, "building the scene", error)) return false;
  build.bytesPerTriangle = (deviceBytes - bytesBefore) / double(terrain.numTriangles());
  // More CPU than wall time would mean that the build ran on more than one thread.
  std::fprintf(stderr, "rays: embree build took %.3f CPU s in %.3f wall s\n",
               build.buildSeconds, wallSeconds);
  figures.builds.push_back(build);

  RTCIntersectContext context;
  rtcInitIntersectContext(&context);

  RayCastFigures single{"embree", "high_quality", 0, RayDistances(rays.size())};
  single.secondsPerBatch = timeFastestPass(single.distances, [&](RayDistances& out) {
    RTCRayHit rayHit;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      setRay(rays, i, rayHit);
      rtcIntersect1(handles.scene, &context, &rayHit);
      out[i] = distanceOf(rayHit.hit.geomID, rayHit.ray.tfar, rays.lengths[i]);
    }
  });
  figures.casts.push_back(std::move(single));

  RayCastFigures packets{"embree16", "high_quality", 0, RayDistances(rays.size())};
  packets.secondsPerBatch = timeFastestPass(packets.distances, [&](RayDistances& out) {
    RTCRayHit16 packet;
    alignas(64) int valid[16];  // Embree loads the mask as one vector
    for (std::size_t first = 0; first < rays.size(); first += 16) {
      for (int k = 0; k < 16; ++k) {
        const std::size_t i = first + k;
        valid[k] = i < rays.size() ? -1 : 0;
        if (!valid[k]) continue;
        packet.ray.org_x[k] = rays.starts[3 * i];
        packet.ray.org_y[k] = rays.starts[3 * i + 1];
        packet.ray.org_z[k] = rays.starts[3 * i + 2];
        packet.ray.dir_x[k] = rays.directions[3 * i];
        packet.ray.dir_y[k] = rays.directions[3 * i + 1];
        packet.ray.dir_z[k] = rays.directions[3 * i + 2];
        packet.ray.tnear[k] = 0;
        packet.ray.tfar[k] = 1;
        packet.ray.time[k] = 0;
        packet.ray.mask[k] = ~0u;
        packet.ray.id[k] = unsigned(i);
        packet.ray.flags[k] = 0;
        packet.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
        packet.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcIntersect16(valid, handles.scene, &context, &packet);
      for (int k = 0; k < 16 && valid[k]; ++k) {
        out[first + k] = distanceOf(packet.hit.geomID[k], packet.ray.tfar[k], rays.lengths[first + k]);
      }
    }
  });
  figures.casts.push_back(std::move(packets));

  std::vector<RTCRayHit> stream(rays.size());
  RayCastFigures streamed{"embree_stream", "high_quality", 0, RayDistances(rays.size())};
  streamed.secondsPerBatch = timeFastestPass(streamed.distances, [&](RayDistances& out) {
    for (std::size_t i = 0; i < rays.size(); ++i) setRay(rays, i, stream[i]);
    rtcIntersect1M(handles.scene, &context, stream.data(), unsigned(stream.size()),
                   sizeof(RTCRayHit));
    for (std::size_t i = 0; i < rays.size(); ++i) {
      out[i] = distanceOf(stream[i].hit.geomID, stream[i].ray.tfar, rays.lengths[i]);
    }
  });
  figures.casts.push_back(std::move(streamed));
  return !deviceFailed(handles.device, "casting rays", error);
}

}  // namespace pfxbench
