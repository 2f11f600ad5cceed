#include "reference/edit_bvh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

namespace sdfbrick::reference {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

SdfBounds empty_box() {
    SdfBounds b{};
    for (int i = 0; i < 3; ++i) {
        b.lo[i] = 1.0f;
        b.hi[i] = -1.0f;
    }
    return b;
}

float round_down(double v) {
    float f = static_cast<float>(v);
    if (static_cast<double>(f) > v) f = std::nextafter(f, -kInf);
    return f;
}

float round_up(double v) {
    float f = static_cast<float>(v);
    if (static_cast<double>(f) < v) f = std::nextafter(f, kInf);
    return f;
}

SdfBounds unite(std::span<const SdfBounds> boxes, std::span<const std::uint32_t> ids) {
    SdfBounds u{};
    for (int i = 0; i < 3; ++i) {
        u.lo[i] = kInf;
        u.hi[i] = -kInf;
    }
    for (const std::uint32_t id : ids) {
        for (int i = 0; i < 3; ++i) {
            u.lo[i] = std::min(u.lo[i], boxes[id].lo[i]);
            u.hi[i] = std::max(u.hi[i], boxes[id].hi[i]);
        }
    }
    return u;
}

void set_child(SdfBvhNode& n, int which, const SdfBounds& b, std::int32_t child) {
    float* lo = which == 0 ? n.lo0 : n.lo1;
    float* hi = which == 0 ? n.hi0 : n.hi1;
    for (int i = 0; i < 3; ++i) {
        lo[i] = b.lo[i];
        hi[i] = b.hi[i];
    }
    n.child[which] = child;
}

struct Builder {
    std::span<const SdfBounds> boxes;
    std::vector<std::uint32_t> order;
    std::vector<SdfBvhNode> nodes;
    int depth = 0;

    double centre(std::uint32_t id, int axis) const {
        return 0.5 * (static_cast<double>(boxes[id].lo[axis]) + static_cast<double>(boxes[id].hi[axis]));
    }

    // Builds the subtree over order[first, last) (at least 2 boxes); returns its node index.
    std::int32_t build(std::size_t first, std::size_t last, int level) {
        depth = std::max(depth, level);
        const auto index = static_cast<std::int32_t>(nodes.size());
        nodes.emplace_back();
        double lo[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                        std::numeric_limits<double>::infinity()};
        double hi[3] = {-lo[0], -lo[1], -lo[2]};
        for (std::size_t k = first; k < last; ++k)
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::min(lo[a], centre(order[k], a));
                hi[a] = std::max(hi[a], centre(order[k], a));
            }
        int axis = 0;
        for (int a = 1; a < 3; ++a)
            if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
        const std::size_t mid = first + (last - first) / 2;
        std::nth_element(order.begin() + static_cast<std::ptrdiff_t>(first), order.begin() + static_cast<std::ptrdiff_t>(mid),
                         order.begin() + static_cast<std::ptrdiff_t>(last), [&](std::uint32_t x, std::uint32_t y) {
                             const double cx = centre(x, axis), cy = centre(y, axis);
                             return cx < cy || (cx == cy && x < y);
                         });
        const std::span<const std::uint32_t> ids(order);
        const std::size_t ranges[2][2] = {{first, mid}, {mid, last}};
        SdfBounds child_box[2];
        std::int32_t child[2];
        for (int c = 0; c < 2; ++c) {
            const std::size_t b = ranges[c][0], e = ranges[c][1];
            child_box[c] = unite(boxes, ids.subspan(b, e - b));
            child[c] = e - b == 1 ? ~static_cast<std::int32_t>(order[b]) : build(b, e, level + 1);
        }
        for (int c = 0; c < 2; ++c) set_child(nodes[static_cast<std::size_t>(index)], c, child_box[c], child[c]);
        return index;
    }
};

}  // namespace

SdfBounds to_float_box(const Aabb& b) {
    if (b.empty()) return empty_box();
    SdfBounds f{};
    for (int i = 0; i < 3; ++i) {
        f.lo[i] = round_down(b.lo[i]);
        f.hi[i] = round_up(b.hi[i]);
    }
    return f;
}

bool contains(const SdfBounds& b, const glm::vec3& p) {
    return p.x >= b.lo[0] && p.x <= b.hi[0] && p.y >= b.lo[1] && p.y <= b.hi[1] && p.z >= b.lo[2] && p.z <= b.hi[2];
}

EditBvh build_edit_bvh(std::span<const SdfBounds> boxes) {
    if (boxes.size() > SDF_MAX_EDITS)
        throw std::invalid_argument(fmt::format("build_edit_bvh: {} boxes, at most {}", boxes.size(), SDF_MAX_EDITS));
    for (std::size_t i = 0; i < boxes.size(); ++i)
        for (int a = 0; a < 3; ++a)
            if (std::isnan(boxes[i].lo[a]) || std::isnan(boxes[i].hi[a]))
                throw std::invalid_argument(fmt::format("build_edit_bvh: box {} has a NaN bound", i));
    EditBvh bvh;
    if (boxes.empty()) return bvh;
    if (boxes.size() == 1) {
        SdfBvhNode root{};
        set_child(root, 0, boxes[0], ~0);
        set_child(root, 1, empty_box(), 0);
        bvh.nodes.push_back(root);
        bvh.depth = 1;
        return bvh;
    }
    Builder b{boxes, {}, {}, 0};
    b.order.resize(boxes.size());
    for (std::size_t i = 0; i < boxes.size(); ++i) b.order[i] = static_cast<std::uint32_t>(i);
    b.nodes.reserve(boxes.size() - 1);
    b.build(0, boxes.size(), 1);
    bvh.nodes = std::move(b.nodes);
    bvh.depth = b.depth;
    return bvh;
}

std::vector<std::uint32_t> boxes_containing(const EditBvh& bvh, std::span<const SdfBounds> boxes, const glm::vec3& p) {
    std::vector<std::uint32_t> out;
    if (bvh.nodes.empty()) return out;
    std::vector<std::int32_t> stack{0};
    while (!stack.empty()) {
        const SdfBvhNode& n = bvh.nodes.at(static_cast<std::size_t>(stack.back()));
        stack.pop_back();
        for (int c = 0; c < 2; ++c) {
            SdfBounds b{};
            for (int i = 0; i < 3; ++i) {
                b.lo[i] = c == 0 ? n.lo0[i] : n.lo1[i];
                b.hi[i] = c == 0 ? n.hi0[i] : n.hi1[i];
            }
            if (!contains(b, p)) continue;
            if (n.child[c] < 0) {
                const auto id = static_cast<std::uint32_t>(~n.child[c]);
                if (contains(boxes[id], p)) out.push_back(id);
            } else {
                stack.push_back(n.child[c]);
            }
        }
    }
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace sdfbrick::reference
