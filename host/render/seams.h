// Seams of an adaptive build: where a leaf meets a leaf of another size. A ray crossing a seam leaves
// one brick's interpolation for a coarser or finer one, and a hit/miss mismatch there would be a
// crack. count_seam_mismatches sorts the hit/miss mismatches of a render against a reference by
// where their surface point lies: within one voxel of a seam, or elsewhere.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <unordered_set>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "image/render_buffer.h"
#include "construct/domain.h"
#include "render/brick_tracer.h"
#include "scene/scene.h"

namespace sdfbrick::render {

// One geometry's leaves on the host, found by level and cell.
class LeafCells {
public:
    explicit LeafCells(const construct::GeometryBuild& b);

    std::size_t leaf_count() const;
    // The level of the leaf whose cell contains p (geometry frame), if any.
    std::optional<int> level_at(const glm::dvec3& p) const;
    // Whether p lies in a leaf, within one of that leaf's voxels of a face across which the space
    // belongs to a leaf of another level.
    bool near_seam(const glm::dvec3& p, int interior) const;
    // Leaves with a face neighbour of another level.
    std::size_t seam_leaves(int interior) const;

private:
    bool has(int level, const glm::ivec3& c) const;
    glm::ivec3 cell_at(int level, const glm::dvec3& p) const;

    construct::Domain domain_;
    int coarsest_ = 0;
    std::vector<std::unordered_set<std::uint64_t>> cells_;  // per level: the leaves' cells
};

struct SeamMismatches {
    std::size_t at_seams = 0;   // hit/miss mismatches whose surface point is within a voxel of a seam
    std::size_t elsewhere = 0;  // the other hit/miss mismatches
    std::size_t seam_leaves = 0;  // leaves (all geometries) with a face neighbour of another level
};
nlohmann::json to_json(const SeamMismatches& s);

// The hit/miss mismatches between test and reference (images of scene through its camera, test
// traced against bricks), sorted by seam. The surface point of a mismatch is the hit of whichever
// image has one; reference pixels flagged unconverged are left out as compare() leaves them out.
SeamMismatches count_seam_mismatches(const Scene& scene, const SceneBricks& bricks, const RenderBuffer& test,
                                     const RenderBuffer& reference);

}  // namespace sdfbrick::render
