// How far the band-limited field F_C (kernels/sdf_build.h) is from the unsaturated field F, in double
// precision on the host, for a guard factor: C = max(half leaf diagonal, band) + guard * largest blend.
// Both are clamped to the stored band and compared at points on and near the surface.
//   build/release/tools/band_limit_error scenes/drops.json [leaf=0.0625] [points=4000]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "reference/reference_field.h"
#include "scene/scene_json.h"

int main(int argc, char** argv) {
    using namespace sdfbrick;
    if (argc < 2) {
        std::fprintf(stderr, "usage: band_limit_error SCENE.json [leaf] [points]\n");
        return 2;
    }
    const Scene file = load_scene(argv[1]);
    const Geometry g = geometry_at(file.geometries.at(0), file.time);
    const double leaf = argc > 2 ? std::atof(argv[2]) : 0.0625;
    const auto count = static_cast<std::size_t>(argc > 3 ? std::atoll(argv[3]) : 4000);
    double k_max = 0.0;
    for (const Edit& e : g.edits) k_max = std::max(k_max, e.blend);
    const double voxel = leaf / 6.0, band = 4.0 * voxel, base = std::max(std::sqrt(3.0) / 2.0 * leaf, band);
    const auto points = reference::near_surface_points(g, count, 7, 1.5 * base);
    std::printf("%s: %zu points within %.4g of the surface, largest blend %.3g, voxel %.4g\n", argv[1], points.size(),
                1.5 * base, k_max, voxel);
    for (double guard : {0.0, 0.5, 1.0, 2.0, 3.0}) {
        const double c = base + guard * k_max;
        double worst = 0.0;
        std::size_t differ = 0;
        for (const glm::dvec3& p : points) {
            double f = reference::kFar, fc = c;
            for (const Edit& e : g.edits) {
                const double v = reference::edit_value(e, p);
                f = reference::combine(e.op, e.blend, f, v);
                fc = std::clamp(reference::combine(e.op, e.blend, fc, v), -c, c);
            }
            const double d = std::abs(std::clamp(f, -band, band) - std::clamp(fc, -band, band));
            differ += d > 0.0;
            worst = std::max(worst, d);
        }
        std::printf("  guard %.1f: C = %.4g, samples that differ %zu (%.2f%%), largest difference %.4f voxels "
                    "(int8 step %.4f voxels)\n",
                    guard, c, differ, 100.0 * double(differ) / double(points.size()), worst / voxel, 4.0 / 127.0);
    }
}
