// ray_embree: the Embree 3 side of bench/ray_bench.sh (a benchmark host,
// not part of ccss; it links no ccss code).
//
//   ray_embree MESH.obj RAYS.txt HITS.txt [REPEATS]
//
// MESH.obj: 'v x y z' and 'f a b c' lines (triangles; 'a/..' index forms
// and negative indices are accepted); RAYS.txt: 'ox oy oz dx dy dz' per
// line ('#' lines skipped), the same file `ccss raycast` reads. HITS.txt:
// per ray the first-hit t of rtcIntersect1 ('%.9e') or 'miss'.
// stdout: one line 'embree triangles=.. rays=.. build_ms=.. ...' with the
// BVH build time (one thread, default quality) and the per-ray time of
// rtcIntersect1 / rtcIntersect4 / rtcIntersect8 (the minimum over REPEATS
// passes, default 10), packets filled with consecutive rays.
//
// Embree works in single precision: the vertices and ray origins are
// shifted by the centre of the vertex box (in double) before rounding to
// float, so the float resolution is that of the model size.
#include <embree3/rtcore.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

struct Ray6 {
  double o[3], d[3];
};

[[noreturn]] void die(const std::string& msg) {
  std::fprintf(stderr, "ray_embree: error: %s\n", msg.c_str());
  std::exit(1);
}

// One OBJ index token ("7", "7/1/2", "-1") as a 0-based vertex index.
long obj_index(const std::string& tok, long nv, long line) {
  long i = std::strtol(tok.c_str(), nullptr, 10);
  if (i < 0) i = nv + i;
  else i -= 1;
  if (i < 0 || i >= nv)
    die("line " + std::to_string(line) + ": vertex index out of range");
  return i;
}

void load_obj(const char* path, std::vector<double>& v, std::vector<unsigned>& tri) {
  std::ifstream f(path);
  if (!f) die(std::string("cannot read ") + path);
  std::string s;
  long line = 0;
  while (std::getline(f, s)) {
    ++line;
    std::istringstream in(s);
    std::string tag;
    in >> tag;
    if (tag == "v") {
      double x, y, z;
      if (!(in >> x >> y >> z)) die("line " + std::to_string(line) + ": bad vertex");
      v.insert(v.end(), {x, y, z});
    } else if (tag == "f") {
      std::vector<long> f;
      std::string tok;
      while (in >> tok) f.push_back(obj_index(tok, long(v.size() / 3), line));
      if (f.size() < 3) die("line " + std::to_string(line) + ": face with < 3 vertices");
      for (size_t k = 1; k + 1 < f.size(); ++k)  // fan (input is triangles)
        tri.insert(tri.end(), {unsigned(f[0]), unsigned(f[k]), unsigned(f[k + 1])});
    }
  }
}

std::vector<Ray6> load_rays(const char* path) {
  std::ifstream f(path);
  if (!f) die(std::string("cannot read ") + path);
  std::vector<Ray6> r;
  std::string s;
  while (std::getline(f, s)) {
    if (s.empty() || s[0] == '#') continue;
    std::istringstream in(s);
    Ray6 q;
    if (!(in >> q.o[0] >> q.o[1] >> q.o[2] >> q.d[0] >> q.d[1] >> q.d[2]))
      die("bad ray line: " + s);
    r.push_back(q);
  }
  return r;
}

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

template <class RH>
void set_ray(RH& rh, int k, const Ray6& q, const double c[3]) {
  rh.ray.org_x[k] = float(q.o[0] - c[0]);
  rh.ray.org_y[k] = float(q.o[1] - c[1]);
  rh.ray.org_z[k] = float(q.o[2] - c[2]);
  rh.ray.dir_x[k] = float(q.d[0]);
  rh.ray.dir_y[k] = float(q.d[1]);
  rh.ray.dir_z[k] = float(q.d[2]);
  rh.ray.tnear[k] = 0.0f;
  rh.ray.tfar[k] = INFINITY;
  rh.ray.time[k] = 0.0f;
  rh.ray.mask[k] = 0xFFFFFFFFu;
  rh.ray.id[k] = 0;
  rh.ray.flags[k] = 0;
  rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
}

// Seconds for one pass of packets of width N over all rays; sums the hit
// t into *sum so the work is not optimised away.
template <int N, class RH, class F>
double packet_pass(RTCScene scene, const std::vector<Ray6>& rays, const double c[3], F intersect,
                   double* sum) {
  alignas(64) RH rh;
  alignas(64) int valid[N];
  RTCIntersectContext ctx;
  double t0 = now_s();
  for (size_t i = 0; i < rays.size(); i += N) {
    for (int k = 0; k < N; ++k) {
      size_t j = std::min(i + k, rays.size() - 1);
      valid[k] = i + k < rays.size() ? -1 : 0;
      set_ray(rh, k, rays[j], c);
    }
    rtcInitIntersectContext(&ctx);
    intersect(valid, scene, &ctx, &rh);
    for (int k = 0; k < N; ++k)
      if (valid[k] && rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID) *sum += rh.ray.tfar[k];
  }
  return now_s() - t0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) die("usage: ray_embree MESH.obj RAYS.txt HITS.txt [REPEATS]");
  int repeats = argc > 4 ? std::max(1, std::atoi(argv[4])) : 10;
  std::vector<double> v;
  std::vector<unsigned> tri;
  load_obj(argv[1], v, tri);
  std::vector<Ray6> rays = load_rays(argv[2]);
  if (tri.empty()) die("no triangles");

  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (size_t i = 0; i < v.size(); i += 3)
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], v[i + k]), hi[k] = std::max(hi[k], v[i + k]);
  double c[3];
  for (int k = 0; k < 3; ++k) c[k] = 0.5 * (lo[k] + hi[k]);

  RTCDevice dev = rtcNewDevice("threads=1");
  if (!dev) die("rtcNewDevice failed");

  // BVH build: geometry creation, buffer fill, commit (minimum of repeats).
  double build_s = INFINITY;
  RTCScene scene = nullptr;
  for (int r = 0; r < repeats; ++r) {
    if (scene) rtcReleaseScene(scene);
    double t0 = now_s();
    scene = rtcNewScene(dev);
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    float* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), v.size() / 3));
    for (size_t i = 0; i < v.size(); ++i) vb[i] = float(v[i] - c[i % 3]);
    unsigned* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), tri.size() / 3));
    std::memcpy(ib, tri.data(), tri.size() * sizeof(unsigned));
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene);
    build_s = std::min(build_s, now_s() - t0);
  }
  if (rtcGetDeviceError(dev) != RTC_ERROR_NONE) die("Embree error during the build");

  // rtcIntersect1: hits written once, time = minimum over repeats.
  std::vector<float> t1(rays.size(), -1.0f);
  double one_s = INFINITY, sum1 = 0.0;
  for (int r = 0; r < repeats; ++r) {
    RTCIntersectContext ctx;
    double t0 = now_s();
    for (size_t i = 0; i < rays.size(); ++i) {
      RTCRayHit rh;
      rh.ray.org_x = float(rays[i].o[0] - c[0]);
      rh.ray.org_y = float(rays[i].o[1] - c[1]);
      rh.ray.org_z = float(rays[i].o[2] - c[2]);
      rh.ray.dir_x = float(rays[i].d[0]);
      rh.ray.dir_y = float(rays[i].d[1]);
      rh.ray.dir_z = float(rays[i].d[2]);
      rh.ray.tnear = 0.0f;
      rh.ray.tfar = INFINITY;
      rh.ray.time = 0.0f;
      rh.ray.mask = 0xFFFFFFFFu;
      rh.ray.id = 0;
      rh.ray.flags = 0;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcInitIntersectContext(&ctx);
      rtcIntersect1(scene, &ctx, &rh);
      if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
        t1[i] = rh.ray.tfar;
        sum1 += rh.ray.tfar;
      }
    }
    one_s = std::min(one_s, now_s() - t0);
  }
  double s4 = INFINITY, s8 = INFINITY, sum4 = 0.0, sum8 = 0.0;
  for (int r = 0; r < repeats; ++r) {
    s4 = std::min(s4, packet_pass<4, RTCRayHit4>(scene, rays, c, rtcIntersect4, &sum4));
    s8 = std::min(s8, packet_pass<8, RTCRayHit8>(scene, rays, c, rtcIntersect8, &sum8));
  }
  bool packets_ok = rtcGetDeviceError(dev) == RTC_ERROR_NONE;

  FILE* out = std::fopen(argv[3], "w");
  if (!out) die(std::string("cannot write ") + argv[3]);
  size_t hits = 0;
  for (float t : t1) {
    if (t < 0.0f) std::fputs("miss\n", out);
    else std::fprintf(out, "%.9e\n", double(t)), ++hits;
  }
  std::fclose(out);

  double n = double(rays.size());
  std::printf(
      "embree triangles=%zu rays=%zu hit_rays=%zu build_ms=%.3f intersect1_us_per_ray=%.4f "
      "intersect4_us_per_ray=%s intersect8_us_per_ray=%s packets_agree=%d\n",
      tri.size() / 3, rays.size(), hits, build_s * 1e3, one_s * 1e6 / n,
      packets_ok ? std::to_string(s4 * 1e6 / n).c_str() : "n/a",
      packets_ok ? std::to_string(s8 * 1e6 / n).c_str() : "n/a",
      int(std::fabs(sum4 - sum1) <= 1e-6 * std::fabs(sum1) &&
          std::fabs(sum8 - sum1) <= 1e-6 * std::fabs(sum1)));
  rtcReleaseScene(scene);
  rtcReleaseDevice(dev);
  return 0;
}
