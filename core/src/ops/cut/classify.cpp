// SPDX-License-Identifier: MIT
// The cut's vertex classification (ops/cut/classify.h), in two passes over parallel chunks: the
// vertices' distances and posed bounds (the bounds give the tolerance), then their snapped
// sides; and the face pass that flags the vertices in use, for a cut that did not flag them in
// its face scan. Every pass is exact (flags, min / max, disjoint writes), so the chunks may
// follow the thread count.
#include "ops/cut/classify.h"

#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <type_traits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "deepcut/core/parallel.h"

namespace deepcut::detail {

void flag_used(const SurfaceMesh& mesh, std::uint8_t* used) {
  const std::size_t nf = mesh.face_slots();
  parallel_for(nf, grain_per_thread(nf, kMinPassGrain), [&](std::size_t b, std::size_t e) {
    const Triangle* faces = mesh.faces().data();
    for (std::size_t f = b; f < e; ++f) {
      const Triangle& t = faces[f];
      set_flag(used, t[0].index);
      set_flag(used, t[1].index);
      set_flag(used, t[2].index);
    }
  });
}

namespace {

// What the vertex passes read and write.
struct Pass {
  const std::uint8_t* used;  // nullptr: every vertex is used
  const glm::vec3* posed;
  float* dist;
  glm::vec3 point, normal;
};

struct Measure {
  BoundingBox box;  // posed bounds of the vertices in use
};

#if defined(__clang__) || (defined(__GNUC__) && __GNUC__ >= 12)
// Four floats as one value (GCC >= 12 / Clang vector extensions: SSE on x86, plain code where
// there is no vector unit); operators act lane by lane.
using Four = float __attribute__((vector_size(16)));

Four four(float x) { return Four{x, x, x, x}; }
#endif

// `measure` of every vertex (all in use), four at a time from `b` while four remain: each lane does
// exactly the scalar loop's operations; the bounds' lanes are folded into the six scalars at the
// end (min / max in another order can change only the sign of a zero bound, which the diagonal
// does not see). Returns where it stopped.
std::size_t measure_fours(const Pass& in, std::size_t b, std::size_t e, float& lx, float& ly, float& lz,
                          float& hx, float& hy, float& hz) {
#if defined(__clang__) || (defined(__GNUC__) && __GNUC__ >= 12)
  static_assert(sizeof(glm::vec3) == 3 * sizeof(float), "positions are packed x, y, z rows");
  const float* pos = reinterpret_cast<const float*>(in.posed);  // x, y, z of each vertex in a row
  float* dist = in.dist;
  const Four ox = four(in.point.x), oy = four(in.point.y), oz = four(in.point.z);
  const Four nx = four(in.normal.x), ny = four(in.normal.y), nz = four(in.normal.z);
  Four minx = four(lx), miny = four(ly), minz = four(lz), maxx = four(hx), maxy = four(hy), maxz = four(hz);
  std::size_t v = b;
  for (; v + 4 <= e; v += 4) {
    Four p0, p1, p2;  // x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3
    std::memcpy(&p0, pos + 3 * v, sizeof(Four));
    std::memcpy(&p1, pos + 3 * v + 4, sizeof(Four));
    std::memcpy(&p2, pos + 3 * v + 8, sizeof(Four));
    // Five shuffles, each two lanes of its first operand then two of its second (one SSE shufps).
    const Four xy = __builtin_shufflevector(p1, p2, 2, 3, 5, 6);  // x2 y2 x3 y3
    const Four yz = __builtin_shufflevector(p0, p1, 1, 2, 4, 5);  // y0 z0 y1 z1
    const Four x = __builtin_shufflevector(p0, xy, 0, 3, 4, 6);
    const Four y = __builtin_shufflevector(yz, xy, 0, 2, 5, 7);
    const Four z = __builtin_shufflevector(yz, p2, 1, 3, 4, 7);
    minx = x < minx ? x : minx;
    miny = y < miny ? y : miny;
    minz = z < minz ? z : minz;
    maxx = maxx < x ? x : maxx;
    maxy = maxy < y ? y : maxy;
    maxz = maxz < z ? z : maxz;
    const Four d = ((x - ox) * nx + (y - oy) * ny) + (z - oz) * nz;  // glm::dot's order
    std::memcpy(dist + v, &d, sizeof(Four));
  }
  for (int k = 0; k < 4; ++k) {
    lx = minx[k] < lx ? minx[k] : lx;
    ly = miny[k] < ly ? miny[k] : ly;
    lz = minz[k] < lz ? minz[k] : lz;
    hx = hx < maxx[k] ? maxx[k] : hx;
    hy = hy < maxy[k] ? maxy[k] : hy;
    hz = hz < maxz[k] ? maxz[k] : hz;
  }
  return v;
#else
  // Compilers without these vector operations leave every vertex to the scalar loop.
  (void)in, (void)e, (void)lx, (void)ly, (void)lz, (void)hx, (void)hy, (void)hz;
  return b;
#endif
}

// Distances of the vertices [b, e) and their posed bounds. kSkipUnused: vertices `in.used` does
// not flag get distance 0 and stay out of the bounds. Otherwise every vertex is in use.
template <bool kSkipUnused>
Measure measure(const Pass& in, std::size_t b, std::size_t e) {
  // Locals, not members: the stores to `dist` could alias them, which would then be read again
  // at every vertex. The box in six scalars, each kept as BoundingBox::add keeps it.
  const std::uint8_t* used = in.used;
  const glm::vec3* pos = in.posed;
  float* dist = in.dist;
  const glm::vec3 o = in.point, n = in.normal;
  BoundingBox part;
  float lx = part.min.x, ly = part.min.y, lz = part.min.z, hx = part.max.x, hy = part.max.y, hz = part.max.z;
  std::size_t v = b;
  if constexpr (!kSkipUnused) v = measure_fours(in, b, e, lx, ly, lz, hx, hy, hz);
  for (; v < e; ++v) {
    if constexpr (kSkipUnused) {
      if (!flag_of(used, v)) {
        dist[v] = 0.0f;
        continue;
      }
    }
    const glm::vec3 p = pos[v];
    lx = p.x < lx ? p.x : lx;
    ly = p.y < ly ? p.y : ly;
    lz = p.z < lz ? p.z : lz;
    hx = hx < p.x ? p.x : hx;
    hy = hy < p.y ? p.y : hy;
    hz = hz < p.z ? p.z : hz;
    dist[v] = glm::dot(p - o, n);
  }
  part.min = glm::vec3(lx, ly, lz);
  part.max = glm::vec3(hx, hy, hz);
  return {part};
}

// The largest float not above `x`: for a float d, d > x exactly when d > float_at_or_below(x)
// (and d < -x exactly when d < -float_at_or_below(x)), so the snapping compares in float.
float float_at_or_below(double x) {
  constexpr float kMax = std::numeric_limits<float>::max();
  if (x >= double(kMax)) return std::isinf(x) ? static_cast<float>(x) : kMax;
  if (x < -double(kMax)) return -std::numeric_limits<float>::infinity();
  float f = static_cast<float>(x);
  if (static_cast<double>(f) > x) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}

// `snap` of every vertex (without kCheckUsed) from `b`, sixteen at a time while sixteen remain:
// each lane compares as the scalar loop does, the masks packed to bytes (-1 or 0). Returns where
// it stopped; ors into `pos` and `neg` whether some vertex was above or below.
std::size_t snap_sixteens(const float* dist, float hi, float lo, std::int8_t* sign, std::uint8_t* bits, std::size_t b,
                          std::size_t e, int& pos, int& neg) {
#if defined(__SSE2__)
  if (lo > hi) return b;  // a negative tolerance: a vertex can be both above and below (scalar loop)
  const __m128 h = _mm_set1_ps(hi), l = _mm_set1_ps(lo);
  const __m128i one = _mm_set1_epi8(1), two = _mm_set1_epi8(2), four_bits = _mm_set1_epi8(4);
  __m128i any_above = _mm_setzero_si128(), any_below = _mm_setzero_si128();
  std::size_t v = b;
  for (; v + 16 <= e; v += 16) {
    __m128 d[4];
    for (int k = 0; k < 4; ++k) d[k] = _mm_loadu_ps(dist + v + 4 * k);
    auto packed = [&](auto compare) {  // sixteen byte masks, in vertex order
      const __m128i m01 = _mm_packs_epi32(_mm_castps_si128(compare(d[0])), _mm_castps_si128(compare(d[1])));
      const __m128i m23 = _mm_packs_epi32(_mm_castps_si128(compare(d[2])), _mm_castps_si128(compare(d[3])));
      return _mm_packs_epi16(m01, m23);
    };
    const __m128i above = packed([&](__m128 x) { return _mm_cmpgt_ps(x, h); });
    const __m128i below = packed([&](__m128 x) { return _mm_cmplt_ps(x, l); });
    // above - below, as -below - -above; bits 1 above, 2 below, 4 neither.
    _mm_storeu_si128(reinterpret_cast<__m128i*>(sign + v), _mm_sub_epi8(below, above));
    const __m128i side = _mm_or_si128(_mm_and_si128(above, one), _mm_and_si128(below, two));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(bits + v),
                     _mm_or_si128(side, _mm_andnot_si128(_mm_or_si128(above, below), four_bits)));
    any_above = _mm_or_si128(any_above, above);
    any_below = _mm_or_si128(any_below, below);
  }
  pos |= _mm_movemask_epi8(any_above) != 0;
  neg |= _mm_movemask_epi8(any_below) != 0;
  return v;
#else
  // Without SSE2 every vertex is left to the scalar loop.
  (void)dist, (void)hi, (void)lo, (void)sign, (void)bits, (void)e, (void)pos, (void)neg;
  return b;
#endif
}

// Sides of the vertices [b, e) from their distances: above `hi`, below `lo`, else on the plane.
// kCheckUsed: vertices not in use are on the plane (needed only when the tolerance is negative:
// otherwise their distance 0 snaps there). Bit 1 of the result: some vertex above; bit 2: below.
template <bool kCheckUsed>
int snap(const Pass& in, float hi, float lo, std::int8_t* sign, std::uint8_t* bits, std::size_t b, std::size_t e) {
  const float* dist = in.dist;
  const std::uint8_t* used = in.used;
  int pos = 0, neg = 0;
  std::size_t first = b;
  if constexpr (!kCheckUsed) first = snap_sixteens(dist, hi, lo, sign, bits, b, e, pos, neg);
  for (std::size_t v = first; v < e; ++v) {
    const float d = dist[v];
    int above = d > hi, below = d < lo;
    if constexpr (kCheckUsed) {
      const int u = flag_of(used, v);
      above &= u;
      below &= u;
    }
    sign[v] = static_cast<std::int8_t>(above - below);
    bits[v] = static_cast<std::uint8_t>(above | (below << 1) | ((1 - above - below) << 2));
    pos |= above;
    neg |= below;
  }
  return pos | (neg << 1);
}

}  // namespace

VertexSides classify_vertices(const SurfaceMesh& mesh, const std::vector<glm::vec3>& posed,
                              const glm::vec3& point, const glm::vec3& normal, float relative_tolerance,
                              std::size_t room, const std::uint8_t* used) {
  const std::size_t nv = mesh.vertex_count();
  VertexSides out;
  out.dist.reserve(room);
  out.sign.reserve(room);
  out.dist.resize(nv);
  out.sign.resize(nv);
  out.bits.resize(nv);
  const Pass in{used, posed.data(), out.dist.data(), point, normal};
  const std::size_t grain = grain_per_thread(nv, kMinPassGrain);
  auto measure_all = [&](auto skip_unused) {
    return parallel_reduce(
        nv, grain, Measure(),
        [&](std::size_t b, std::size_t e) { return measure<decltype(skip_unused)::value>(in, b, e); },
        [](Measure acc, const Measure& part) {
          acc.box.add(part.box);
          return acc;
        });
  };
  const Measure m = used ? measure_all(std::true_type()) : measure_all(std::false_type());
  const double tol = double(relative_tolerance) * double(m.box.diagonal());
  const float hi = float_at_or_below(tol), lo = -hi;
  const bool check_used = used && !(tol >= 0.0);
  std::int8_t* sign = out.sign.data();
  std::uint8_t* bits = out.bits.data();
  const int sides = parallel_reduce(
      nv, grain, 0,
      [&](std::size_t b, std::size_t e) {
        return check_used ? snap<true>(in, hi, lo, sign, bits, b, e) : snap<false>(in, hi, lo, sign, bits, b, e);
      },
      [](int acc, int part) { return acc | part; });
  out.both_sides = sides == 3;
  return out;
}

}  // namespace deepcut::detail
