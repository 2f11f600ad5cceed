#include "reference/accuracy.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/stats.h"
#include "reference/host_tracer.h"

namespace sdfbrick::reference {

namespace {

constexpr double kPi = 3.14159265358979323846;

void check_pair(const RenderBuffer& test, const RenderBuffer& reference, double voxel_world) {
    test.check("test");
    reference.check("reference");
    if (test.width != reference.width || test.height != reference.height)
        throw std::invalid_argument("accuracy: image sizes differ: test " + std::to_string(test.width) + " x " +
                                    std::to_string(test.height) + ", reference " + std::to_string(reference.width) +
                                    " x " + std::to_string(reference.height));
    if (!(voxel_world > 0.0) || !std::isfinite(voxel_world))
        throw std::invalid_argument("accuracy: voxel_world must be a finite value > 0, got " + std::to_string(voxel_world));
}

void check_voxels(std::span<const double> pixel_voxel, std::size_t pixels) {
    if (pixel_voxel.size() != pixels)
        throw std::invalid_argument("accuracy: " + std::to_string(pixel_voxel.size()) + " pixel voxels for " +
                                    std::to_string(pixels) + " pixels");
    for (const double v : pixel_voxel)
        if (!(v > 0.0) || !std::isfinite(v))
            throw std::invalid_argument("accuracy: a pixel's voxel must be a finite value > 0, got " + std::to_string(v));
}

bool unconverged(const RenderBuffer& reference, std::size_t i) { return (reference.aux[i].s[1] & SDF_REF_UNCONVERGED) != 0u; }

double depth_of(const RenderBuffer& b, std::size_t i) { return static_cast<double>(b.hit[i].s[3]); }

double angle_deg(const glm::dvec3& a, const glm::dvec3& b) {
    const double la = glm::length(a), lb = glm::length(b);
    if (!(la > 0.0) || !(lb > 0.0) || !std::isfinite(la) || !std::isfinite(lb)) return 180.0;
    const glm::dvec3 na = a / la, nb = b / lb;
    return std::atan2(glm::length(glm::cross(na, nb)), glm::dot(na, nb)) * (180.0 / kPi);
}

double mean(const std::vector<double>& v) {
    if (v.empty()) return 0.0;
    double s = 0.0;
    for (double x : v) s += x;
    return s / static_cast<double>(v.size());
}

glm::dvec3 heat(double e) {
    if (std::isnan(e)) e = 1.0;  // e.g. inf - inf: shown as the worst error
    e = std::clamp(e, 0.0, 1.0);
    const glm::dvec3 stops[4] = {glm::dvec3(0.15), glm::dvec3(1.0, 0.0, 0.0), glm::dvec3(1.0, 1.0, 0.0), glm::dvec3(1.0)};
    const double x = e * 3.0;
    const int seg = std::min(static_cast<int>(x), 2);
    const double f = x - seg;
    return stops[seg] * (1.0 - f) + stops[seg + 1] * f;
}

// compare() with pixel i's voxel given by voxel(i).
template <class Voxel>
AccuracyMetrics compare_with(const RenderBuffer& test, const RenderBuffer& reference, Voxel&& voxel) {
    AccuracyMetrics m;
    std::vector<double> depth_err, depth_world, normal_err;
    double sq = 0.0;
    for (std::size_t i = 0; i < reference.pixels(); ++i) {
        if (unconverged(reference, i)) {
            ++m.reference_unconverged;
            continue;
        }
        ++m.pixels;
        const bool ht = test.is_hit(i), hr = reference.is_hit(i);
        if (ht != hr) ++m.hit_mismatches;
        if (ht && hr) {
            ++m.both_hit;
            depth_world.push_back(std::abs(depth_of(test, i) - depth_of(reference, i)));
            depth_err.push_back(depth_world.back() / voxel(i));
            normal_err.push_back(angle_deg(test.normal(i), reference.normal(i)));
        }
        const glm::dvec3 d = normal_colour(test, i) - normal_colour(reference, i);
        sq += glm::dot(d, d);
    }
    m.mismatch_fraction = m.pixels == 0 ? 0.0 : static_cast<double>(m.hit_mismatches) / static_cast<double>(m.pixels);
    m.depth_error_mean = mean(depth_err);
    m.depth_error_max = depth_err.empty() ? 0.0 : *std::max_element(depth_err.begin(), depth_err.end());
    m.depth_error_p99 = percentile(std::move(depth_err), 99.0);
    m.depth_error_max_world = depth_world.empty() ? 0.0 : *std::max_element(depth_world.begin(), depth_world.end());
    m.depth_error_p99_world = percentile(std::move(depth_world), 99.0);
    m.normal_error_mean_deg = mean(normal_err);
    m.normal_error_p99_deg = percentile(std::move(normal_err), 99.0);
    const double mse = m.pixels == 0 ? 0.0 : sq / (3.0 * static_cast<double>(m.pixels));
    m.psnr_db = mse > 0.0 ? 10.0 * std::log10(1.0 / mse) : std::numeric_limits<double>::infinity();
    return m;
}

}  // namespace

AccuracyMetrics compare(const RenderBuffer& test, const RenderBuffer& reference, double voxel_world) {
    check_pair(test, reference, voxel_world);
    return compare_with(test, reference, [voxel_world](std::size_t) { return voxel_world; });
}

AccuracyMetrics compare(const RenderBuffer& test, const RenderBuffer& reference, std::span<const double> pixel_voxel) {
    check_pair(test, reference, 1.0);
    check_voxels(pixel_voxel, reference.pixels());
    return compare_with(test, reference, [pixel_voxel](std::size_t i) { return pixel_voxel[i]; });
}

void add_surface_error(AccuracyMetrics& m, const RenderBuffer& test, const RenderBuffer& reference,
                       const HostCamera& camera) {
    check_pair(test, reference, 1.0);
    if (camera.width != reference.width || camera.height != reference.height)
        throw std::invalid_argument("accuracy: the camera's image size differs from the images'");
    const auto width = static_cast<std::size_t>(reference.width);
    std::vector<double> err;
    for (std::size_t i = 0; i < reference.pixels(); ++i) {
        if (unconverged(reference, i) || !test.is_hit(i) || !reference.is_hit(i)) continue;
        const glm::dvec3 d = camera.direction(static_cast<int>(i % width), static_cast<int>(i / width));
        const double c = std::abs(glm::dot(d, reference.normal(i)));
        err.push_back(std::abs(depth_of(test, i) - depth_of(reference, i)) * c);
    }
    m.surface_error_max_world = err.empty() ? 0.0 : *std::max_element(err.begin(), err.end());
    m.surface_error_p99_world = percentile(std::move(err), 99.0);
}

nlohmann::json to_json(const AccuracyMetrics& m) {
    nlohmann::json j;
    j["pixels"] = m.pixels;
    j["both_hit"] = m.both_hit;
    j["hit_mismatches"] = m.hit_mismatches;
    j["mismatch_fraction"] = m.mismatch_fraction;
    j["depth_error_mean"] = m.depth_error_mean;
    j["depth_error_p99"] = m.depth_error_p99;
    j["depth_error_max"] = m.depth_error_max;
    j["depth_error_p99_world"] = m.depth_error_p99_world;
    j["depth_error_max_world"] = m.depth_error_max_world;
    if (m.surface_error_p99_world) {
        j["surface_error_p99_world"] = *m.surface_error_p99_world;
        j["surface_error_max_world"] = *m.surface_error_max_world;
    }
    j["normal_error_mean_deg"] = m.normal_error_mean_deg;
    j["normal_error_p99_deg"] = m.normal_error_p99_deg;
    j["psnr_db"] = std::isfinite(m.psnr_db) ? nlohmann::json(m.psnr_db) : nlohmann::json(nullptr);
    j["reference_unconverged"] = m.reference_unconverged;
    return j;
}

Image difference_image(const RenderBuffer& test, const RenderBuffer& reference, double voxel_world,
                       double saturation_voxels) {
    check_pair(test, reference, voxel_world);
    return difference_image(test, reference, std::vector<double>(reference.pixels(), voxel_world), saturation_voxels);
}

Image difference_image(const RenderBuffer& test, const RenderBuffer& reference, std::span<const double> pixel_voxel,
                       double saturation_voxels) {
    check_pair(test, reference, 1.0);
    check_voxels(pixel_voxel, reference.pixels());
    if (!(saturation_voxels > 0.0) || !std::isfinite(saturation_voxels))
        throw std::invalid_argument("accuracy: saturation_voxels must be a finite value > 0");
    Image im(test.width, test.height, 3);
    for (std::size_t i = 0; i < reference.pixels(); ++i) {
        glm::dvec3 c(0.0);
        const bool ht = test.is_hit(i), hr = reference.is_hit(i);
        if (unconverged(reference, i)) {
            c = glm::dvec3(0.0, 0.0, 1.0);
        } else if (ht && !hr) {
            c = glm::dvec3(1.0, 0.0, 1.0);
        } else if (!ht && hr) {
            c = glm::dvec3(0.0, 1.0, 1.0);
        } else if (ht && hr) {
            c = heat(std::abs(depth_of(test, i) - depth_of(reference, i)) / pixel_voxel[i] / saturation_voxels);
        }
        set_pixel(im, i, c);
    }
    return im;
}

}  // namespace sdfbrick::reference
