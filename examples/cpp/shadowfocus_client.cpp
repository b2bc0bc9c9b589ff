// A C++17 client of the shadowfocus C ABI: cascaded LiSPSM maps for a sun and
// a spot light along a 300-frame walk through a 200 m scene. Every map is
// checked against its focus body: each vertex inside the clip volume (in
// double and, where f32_exact, with the float matrix in float) and inside
// the lookup's [0, 1] range; every fourth frame also in OpenGL's clip
// convention with reversed-Z. A grid of caster boxes is culled, and tested
// against the caster planes as an engine's own culling would (it must keep
// the same boxes); the error paths are exercised and a summary is printed.
// Exits non-zero on any violation or unexpected error.
//
// Build and run: examples/cpp/run.sh

#include "shadowfocus.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

static_assert(sizeof(SfMethod) == sizeof(int), "C enums are int-sized");
static_assert(sizeof(SfLightKind) == sizeof(int), "C enums are int-sized");

namespace {

constexpr int kFrames = 300;
constexpr double kPi = 3.14159265358979323846;

// The walk: a circle of radius 70 m around the scene's centre, looking
// ahead along it and swinging left and right. rust_loop.rs uses the same.
SfCamera camera_at(int k) {
    const double a = 2.0 * kPi * k / kFrames;
    const double yaw = a + kPi / 2.0 + 0.5 * std::sin(3.0 * a);
    SfCamera c{};
    c.eye[0] = 70.0 * std::cos(a);
    c.eye[1] = 1.8 + 0.3 * std::sin(7.0 * a);
    c.eye[2] = 70.0 * std::sin(a);
    c.forward[0] = std::cos(yaw);
    c.forward[1] = -0.1 + 0.05 * std::sin(2.0 * a);
    c.forward[2] = std::sin(yaw);
    c.up[1] = 1.0;
    c.fovy_rad = 60.0 * kPi / 180.0;
    c.aspect = 16.0 / 9.0;
    c.near_dist = 0.3;
    c.far_dist = 200.0;
    return c;
}

SfLight sun() {
    SfLight l{};
    l.kind = SF_LIGHT_DIRECTIONAL;
    l.direction[0] = 0.4;
    l.direction[1] = -1.0;
    l.direction[2] = 0.3;
    return l;
}

SfLight spot() {
    SfLight l{};
    l.kind = SF_LIGHT_SPOT;
    l.position[1] = 35.0;
    l.direction[0] = 0.3;
    l.direction[1] = -1.0;
    l.direction[2] = 0.2;
    l.up[1] = 1.0;
    l.fovy_rad = kPi / 2.0;
    l.aspect = 1.0;
    l.near_dist = 0.5;
    l.far_dist = 120.0;
    return l;
}

SfAabb scene_box() {
    return SfAabb{{-100.0, 0.0, -100.0}, {100.0, 40.0, 100.0}};
}

// A 20 x 20 grid of caster boxes, 2 m wide, 1 to 10 m tall.
std::vector<SfAabb> caster_grid() {
    std::vector<SfAabb> boxes;
    for (int i = 0; i < 20; ++i) {
        for (int j = 0; j < 20; ++j) {
            const double x = -95.0 + 10.0 * i, z = -95.0 + 10.0 * j;
            boxes.push_back(SfAabb{{x - 1.0, 0.0, z - 1.0}, {x + 1.0, 1.0 + (i * 7 + j * 3) % 10, z + 1.0}});
        }
    }
    return boxes;
}

// Row r of the column-major matrix m times (x, y, z, 1), left to right.
template <typename T>
T row(const T* m, int r, T x, T y, T z) {
    return m[r] * x + m[4 + r] * y + m[8 + r] * z + m[12 + r];
}

// The clip volume with depth in [z_lo, 1]: z_lo is 0, or -1 for OpenGL's range.
template <typename T>
bool inside(const T* m, T x, T y, T z, T z_lo) {
    const T cx = row(m, 0, x, y, z), cy = row(m, 1, x, y, z), cz = row(m, 2, x, y, z), cw = row(m, 3, x, y, z);
    return cw > T(0) && -cw <= cx && cx <= cw && -cw <= cy && cy <= cw && z_lo * cw <= cz && cz <= cw;
}

// The lookup matrix puts the point at u, v, depth in [0, 1] (to a few ulps).
bool in_lookup(const double* m, double x, double y, double z) {
    const double w = row(m, 3, x, y, z), tol = 1e-9;
    for (int r = 0; r < 3; ++r) {
        const double c = row(m, r, x, y, z) / w;
        if (!(c >= -tol && c <= 1.0 + tol)) {
            return false;
        }
    }
    return w > 0.0;
}

// A box outside one caster plane by more than its rounding casts no shadow.
bool outside_planes(const double* planes, size_t n, const SfAabb& box) {
    double c[3], e[3], mag = 0.0;
    for (int k = 0; k < 3; ++k) {
        c[k] = 0.5 * (box.min[k] + box.max[k]);
        e[k] = 0.5 * (box.max[k] - box.min[k]);
        mag = std::max(mag, std::max(std::fabs(box.min[k]), std::fabs(box.max[k])));
    }
    const double slack = mag * std::ldexp(1.0, -36);
    for (size_t p = 0; p < n; ++p) {
        const double* q = &planes[4 * p];
        double s = q[3];
        for (int k = 0; k < 3; ++k) {
            s += q[k] * c[k] - std::fabs(q[k]) * e[k];
        }
        if (s > slack) {
            return true;
        }
    }
    return false;
}

struct Tally {
    long fits = 0;
    long maps = 0;
    long active = 0;
    long vertices = 0;
    long vertices_f32 = 0;
    long violations = 0;
    long casters_tested = 0;
    long casters_kept = 0;
    long errors = 0;
    double fit_us[2] = {0.0, 0.0};
    long fits_of[2] = {0, 0};
};

void report(SfContext* ctx, const char* what, int rc, Tally& t) {
    std::fprintf(stderr, "%s failed with %d: %s\n", what, rc, sf_last_error(ctx));
    ++t.errors;
}

// Checks every vertex of map i's body against its matrices.
void check_body(SfContext* ctx, size_t i, const SfMap& map, double z_lo, std::vector<double>& verts, Tally& t) {
    size_t n = 0;
    const int rc = sf_body(ctx, i, verts.data(), verts.size() / 3, &n);
    if (rc != SF_OK) {
        report(ctx, "sf_body", rc, t);
        return;
    }
    if (n != map.body_vertex_count) {
        std::fprintf(stderr, "map %zu: %zu body vertices, body_vertex_count %u\n", i, n, map.body_vertex_count);
        ++t.violations;
    }
    for (size_t v = 0; v < n; ++v) {
        const double* p = &verts[3 * v];
        ++t.vertices;
        if (!inside(map.clip_from_world, p[0], p[1], p[2], z_lo) || !in_lookup(map.uv_from_world, p[0], p[1], p[2])) {
            std::fprintf(stderr, "map %zu: vertex (%g, %g, %g) outside the f64 clip volume or lookup\n", i, p[0], p[1], p[2]);
            ++t.violations;
        }
        if (map.f32_exact) {
            ++t.vertices_f32;
            const float x = static_cast<float>(p[0]), y = static_cast<float>(p[1]), z = static_cast<float>(p[2]);
            if (!inside(map.clip_from_world_f32, x, y, z, static_cast<float>(z_lo))) {
                std::fprintf(stderr, "map %zu: vertex (%g, %g, %g) outside the f32 clip volume\n", i, p[0], p[1], p[2]);
                ++t.violations;
            }
        }
    }
}

void cull(SfContext* ctx, size_t i, const std::vector<SfAabb>& boxes, std::vector<uint32_t>& kept, Tally& t) {
    size_t n = 0;
    const int rc = sf_cull_casters(ctx, i, boxes.data(), boxes.size(), kept.data(), kept.size(), &n);
    if (rc != SF_OK) {
        report(ctx, "sf_cull_casters", rc, t);
        return;
    }
    for (size_t k = 0; k < n; ++k) {
        if (kept[k] >= boxes.size() || (k > 0 && kept[k] <= kept[k - 1])) {
            std::fprintf(stderr, "map %zu: culling gave a bad index %u\n", i, kept[k]);
            ++t.violations;
        }
    }
    // The engine's own test against the caster planes keeps the same boxes.
    std::array<double, 4 * SF_MAX_CASTER_PLANES> planes{};
    size_t np = 0;
    if (sf_caster_planes(ctx, i, planes.data(), SF_MAX_CASTER_PLANES, &np) != SF_OK) {
        report(ctx, "sf_caster_planes", -1, t);
        return;
    }
    size_t next = 0;
    for (size_t b = 0; b < boxes.size(); ++b) {
        const bool keep = !outside_planes(planes.data(), np, boxes[b]);
        const bool kept_by_cull = next < n && kept[next] == b;
        next += kept_by_cull ? 1 : 0;
        if (keep != kept_by_cull) {
            std::fprintf(stderr, "map %zu: box %zu kept %d by the planes, %d by sf_cull_casters\n", i, b, keep, kept_by_cull);
            ++t.violations;
        }
    }
    t.casters_tested += static_cast<long>(boxes.size());
    t.casters_kept += static_cast<long>(n);
}

// One light in one frame: fit (timed), then check and cull every active map.
void fit_light(SfContext* ctx, int which, const SfCamera& cam, const SfLight& light, const SfSettings& settings,
               std::vector<SfMap>& maps, std::vector<double>& verts, const std::vector<SfAabb>& boxes,
               std::vector<uint32_t>& kept, Tally& t) {
    const SfAabb scene = scene_box();
    size_t count = 0;
    const auto start = std::chrono::steady_clock::now();
    const int rc = sf_fit(ctx, &cam, &light, &scene, &settings, maps.data(), maps.size(), &count);
    const auto stop = std::chrono::steady_clock::now();
    t.fit_us[which] += std::chrono::duration<double, std::micro>(stop - start).count();
    ++t.fits_of[which];
    ++t.fits;
    if (rc != SF_OK) {
        report(ctx, "sf_fit", rc, t);
        return;
    }
    if (std::strcmp(sf_last_error(ctx), "") != 0) {
        std::fprintf(stderr, "sf_fit succeeded but left the message \"%s\"\n", sf_last_error(ctx));
        ++t.violations;
    }
    t.maps += static_cast<long>(count);
    for (size_t i = 0; i < count; ++i) {
        if (!maps[i].active) {
            continue;
        }
        ++t.active;
        // Sun and spot are never inverted: reversed-Z alone decides the test.
        if ((maps[i].depth_greater != 0) != (settings.reversed_z != 0) || maps[i].inverted) {
            std::fprintf(stderr, "map %zu: depth_greater %d with reversed_z %d\n", i, maps[i].depth_greater, settings.reversed_z);
            ++t.violations;
        }
        check_body(ctx, i, maps[i], settings.depth_zero_to_one ? 0.0 : -1.0, verts, t);
        cull(ctx, i, boxes, kept, t);
    }
}

// The documented failures: near >= far, a bad enum value, a size query.
bool error_paths_behave(SfContext* ctx, const SfSettings& settings) {
    bool ok = true;
    SfCamera cam = camera_at(0);
    cam.far_dist = cam.near_dist;
    const SfLight light = sun();
    const SfAabb scene = scene_box();
    std::array<SfMap, SF_MAX_MAPS> maps{};
    size_t count = 99;
    int rc = sf_fit(ctx, &cam, &light, &scene, &settings, maps.data(), maps.size(), &count);
    std::printf("near >= far: code %d, \"%s\"\n", rc, sf_last_error(ctx));
    ok = ok && rc == SF_ERR_INVALID_INPUT && std::strlen(sf_last_error(ctx)) > 0 && count == 0;

    SfSettings bad = settings;
    bad.method = static_cast<SfMethod>(17);
    rc = sf_fit(ctx, &cam, &light, &scene, &bad, maps.data(), maps.size(), &count);
    ok = ok && rc == SF_ERR_INVALID_INPUT && std::strstr(sf_last_error(ctx), "SfMethod") != nullptr;

    const SfCamera good = camera_at(0);
    rc = sf_fit(ctx, &good, &light, &scene, &settings, nullptr, 0, &count);
    std::printf("size query: code %d, %zu maps needed\n", rc, count);
    ok = ok && rc == SF_ERR_BUFFER_TOO_SMALL && count == settings.splits;
    ok = ok && std::strcmp(sf_last_error(nullptr), "") == 0;
    return ok;
}

}  // namespace

int main() {
    SfContext* ctx = sf_context_new();
    if (ctx == nullptr) {
        std::fprintf(stderr, "sf_context_new failed\n");
        return 1;
    }
    SfSettings settings;
    sf_settings_default(&settings);
    settings.method = SF_METHOD_LISPSM;
    settings.splits = 4;
    settings.resolution = 2048;
    // Every fourth frame also as an OpenGL engine with reversed-Z would fit it.
    SfSettings gl_reversed = settings;
    gl_reversed.depth_zero_to_one = 0;
    gl_reversed.reversed_z = 1;
    gl_reversed.uv_origin_top_left = 0;

    std::vector<SfMap> maps(SF_MAX_MAPS);
    std::vector<double> verts(3 * SF_MAX_BODY_VERTICES);
    const std::vector<SfAabb> boxes = caster_grid();
    std::vector<uint32_t> kept(boxes.size());
    const SfLight lights[2] = {sun(), spot()};

    Tally t;
    for (int k = 0; k < kFrames; ++k) {
        const SfCamera cam = camera_at(k);
        for (int which = 0; which < 2; ++which) {
            fit_light(ctx, which, cam, lights[which], settings, maps, verts, boxes, kept, t);
        }
        if (k % 4 == 0) {
            for (int which = 0; which < 2; ++which) {
                fit_light(ctx, which, cam, lights[which], gl_reversed, maps, verts, boxes, kept, t);
            }
        }
    }
    const bool errors_ok = error_paths_behave(ctx, settings);
    sf_context_free(ctx);

    std::printf("shadowfocus %s C ABI, C++ client\n", sf_version());
    std::printf("frames %d, fits %ld, maps %ld (active %ld)\n", kFrames, t.fits, t.maps, t.active);
    std::printf("body vertices checked %ld (f64), %ld (f32), violations %ld, errors %ld\n", t.vertices, t.vertices_f32,
                t.violations, t.errors);
    std::printf("casters tested %ld, kept %ld (%.1f%%)\n", t.casters_tested, t.casters_kept,
                t.casters_tested ? 100.0 * t.casters_kept / t.casters_tested : 0.0);
    std::printf("mean sf_fit: %.2f us (sun %.2f us, spot %.2f us)\n", (t.fit_us[0] + t.fit_us[1]) / t.fits,
                t.fit_us[0] / t.fits_of[0], t.fit_us[1] / t.fits_of[1]);
    std::printf("error paths: %s\n", errors_ok ? "as documented" : "NOT as documented");
    const bool pass = t.violations == 0 && t.errors == 0 && errors_ok && t.active > 0 && t.vertices > 0;
    std::printf("%s\n", pass ? "PASS" : "FAIL");
    return pass ? 0 : 1;
}
