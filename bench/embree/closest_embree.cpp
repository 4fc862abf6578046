// closest_embree: the Embree 3 side of bench/closest_bench.sh (a benchmark
// host, not part of ccss; it links no ccss code).
//
//   closest_embree MESH.obj POINTS.txt DIST.txt [REPEATS]
//
// MESH.obj: 'v x y z' and 'f a b c ...' lines (faces fanned into
// triangles); POINTS.txt: 'x y z' per line ('#' lines skipped), the file
// `ccss closest` reads. DIST.txt: per point the distance to the nearest
// triangle ('%.9e'). stdout: one line 'embree triangles=.. points=..
// build_ms=.. closest_us_per_point=..' with the BVH build time (one
// thread) and the per-point time of rtcPointQuery (minimum over REPEATS
// passes, default 10).
//
// rtcPointQuery walks the BVH with a sphere of shrinking radius and calls
// back for every triangle whose box meets it; the callback computes the
// exact closest point of that triangle in double precision (vertices and
// points shifted by the centre of the vertex box, as in ray_embree) and
// shrinks the radius. The BVH boxes are single precision: Embree culls
// with them, the distance itself is double.
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

[[noreturn]] void die(const std::string& msg) {
  std::fprintf(stderr, "closest_embree: error: %s\n", msg.c_str());
  std::exit(1);
}

long obj_index(const std::string& tok, long nv, long line) {
  long i = std::strtol(tok.c_str(), nullptr, 10);
  if (i < 0) i = nv + i;
  else i -= 1;
  if (i < 0 || i >= nv) die("line " + std::to_string(line) + ": vertex index out of range");
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
      for (size_t k = 1; k + 1 < f.size(); ++k)
        tri.insert(tri.end(), {unsigned(f[0]), unsigned(f[k]), unsigned(f[k + 1])});
    }
  }
}

struct V3 {
  double x, y, z;
};
V3 sub(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 add(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 mul(V3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// Closest point of triangle abc to p (Voronoi regions of the vertices,
// edges and face, in barycentric terms).
V3 closest_on_triangle(V3 p, V3 a, V3 b, V3 c) {
  V3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  V3 bp = sub(p, b);
  double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return add(a, mul(ab, d1 / (d1 - d3)));
  V3 cp = sub(p, c);
  double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return add(a, mul(ac, d2 / (d2 - d6)));
  double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return add(b, mul(sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6))));
  double den = 1.0 / (va + vb + vc);
  return add(a, add(mul(ab, vb * den), mul(ac, vc * den)));
}

struct Query {
  const std::vector<V3>* v;
  const std::vector<unsigned>* tri;
  V3 p;
  double best;
};

bool point_query(RTCPointQueryFunctionArguments* args) {
  Query* q = static_cast<Query*>(args->userPtr);
  const unsigned* t = q->tri->data() + 3 * size_t(args->primID);
  const std::vector<V3>& v = *q->v;
  V3 x = closest_on_triangle(q->p, v[t[0]], v[t[1]], v[t[2]]);
  V3 d = sub(x, q->p);
  double dist = std::sqrt(dot(d, d));
  if (dist < q->best) {
    q->best = dist;
    args->query->radius = float(dist);
    return true;
  }
  return false;
}

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) die("usage: closest_embree MESH.obj POINTS.txt DIST.txt [REPEATS]");
  int repeats = argc > 4 ? std::max(1, std::atoi(argv[4])) : 10;
  std::vector<double> vd;
  std::vector<unsigned> tri;
  load_obj(argv[1], vd, tri);
  if (tri.empty()) die("no triangles");
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (size_t i = 0; i < vd.size(); i += 3)
    for (int k = 0; k < 3; ++k)
      lo[k] = std::min(lo[k], vd[i + k]), hi[k] = std::max(hi[k], vd[i + k]);
  double c[3];
  for (int k = 0; k < 3; ++k) c[k] = 0.5 * (lo[k] + hi[k]);
  std::vector<V3> v(vd.size() / 3);
  for (size_t i = 0; i < v.size(); ++i)
    v[i] = {vd[3 * i] - c[0], vd[3 * i + 1] - c[1], vd[3 * i + 2] - c[2]};

  std::vector<V3> pts;
  {
    std::ifstream f(argv[2]);
    if (!f) die(std::string("cannot read ") + argv[2]);
    std::string s;
    while (std::getline(f, s)) {
      if (s.empty() || s[0] == '#') continue;
      std::istringstream in(s);
      double x, y, z;
      if (!(in >> x >> y >> z)) die("bad point line: " + s);
      pts.push_back({x - c[0], y - c[1], z - c[2]});
    }
  }

  RTCDevice dev = rtcNewDevice("threads=1");
  if (!dev) die("rtcNewDevice failed");
  double build_s = INFINITY;
  RTCScene scene = nullptr;
  for (int r = 0; r < repeats; ++r) {
    if (scene) rtcReleaseScene(scene);
    double t0 = now_s();
    scene = rtcNewScene(dev);
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    float* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), v.size()));
    for (size_t i = 0; i < v.size(); ++i)
      vb[3 * i] = float(v[i].x), vb[3 * i + 1] = float(v[i].y), vb[3 * i + 2] = float(v[i].z);
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

  std::vector<double> dist(pts.size());
  double best_s = INFINITY;
  for (int r = 0; r < repeats; ++r) {
    double t0 = now_s();
    for (size_t i = 0; i < pts.size(); ++i) {
      Query q{&v, &tri, pts[i], INFINITY};
      RTCPointQuery pq;
      pq.x = float(pts[i].x);
      pq.y = float(pts[i].y);
      pq.z = float(pts[i].z);
      pq.time = 0.0f;
      pq.radius = INFINITY;
      RTCPointQueryContext ctx;
      rtcInitPointQueryContext(&ctx);
      rtcPointQuery(scene, &pq, &ctx, point_query, &q);
      dist[i] = q.best;
    }
    best_s = std::min(best_s, now_s() - t0);
  }
  if (rtcGetDeviceError(dev) != RTC_ERROR_NONE) die("Embree error during the queries");
  FILE* out = std::fopen(argv[3], "w");
  if (!out) die(std::string("cannot write ") + argv[3]);
  for (double d : dist) std::fprintf(out, "%.9e\n", d);
  std::fclose(out);
  std::printf("embree triangles=%zu points=%zu build_ms=%.3f closest_us_per_point=%.4f\n",
              tri.size() / 3, pts.size(), build_s * 1e3, best_s * 1e6 / double(pts.size()));
  rtcReleaseScene(scene);
  rtcReleaseDevice(dev);
  return 0;
}
