// Reading a JSON document with its place in every message (inside scene/: the scene file and the
// edit log): a value, its JSON path and its origin (a file, "file:line"), with typed accessors
// whose refusals are InputErrors of one line, "origin: /json/path: what", every echoed byte escaped.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "core/quote.h"
#include "scene/scene_json.h"

namespace sdfbrick::detail {

using nlohmann::json;

// A position in the document: the value, its JSON path, and the file, for error messages. The node
// keeps a view of origin, which must outlive it.
class Node {
public:
    Node(const json& value, std::string path, std::string_view origin)
        : value_(value), path_(std::move(path)), origin_(origin) {}

    // The place in the input: "origin: /json/path".
    std::string where() const { return fmt::format("{}: {}", origin_, path_.empty() ? "/" : shortened_path(path_)); }
    [[noreturn]] void fail(const std::string& what) const {
        throw InputError(fmt::format("{}: {}", where(), what));
    }

    const json& value() const { return value_; }
    const std::string& path() const { return path_; }

    // Objects: the keys it may have; anything else is refused (catches typos such as "radus").
    void expect_object(std::initializer_list<std::string_view> allowed) const {
        expect_keys(std::vector<std::string_view>(allowed), "this object");
    }
    void expect_keys(const std::vector<std::string_view>& allowed, std::string_view what) const {
        if (!value_.is_object()) fail("expected an object, got " + type_name());
        for (const auto& [key, v] : value_.items()) {
            if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
            std::string list;
            for (auto a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
            Node(v, path_ + "/" + key, origin_).fail(fmt::format("unknown field (for {}: {})", what, list));
        }
    }
    bool has(std::string_view key) const { return value_.contains(key); }
    Node operator[](std::string_view key) const {
        auto it = value_.find(key);
        if (it == value_.end()) fail(fmt::format("missing field \"{}\"", key));
        return Node(*it, path_ + "/" + std::string(key), origin_);
    }
    Node at(std::size_t i) const { return Node(value_.at(i), fmt::format("{}/{}", path_, i), origin_); }

    std::size_t array_size() const {
        if (!value_.is_array()) fail("expected an array, got " + type_name());
        return value_.size();
    }
    std::string string() const {
        if (!value_.is_string()) fail("expected a string, got " + type_name());
        return value_.get<std::string>();
    }
    double number() const {
        if (!value_.is_number()) fail("expected a number, got " + type_name());
        const double v = value_.get<double>();
        if (!std::isfinite(v)) fail("number is not finite");
        if (std::abs(v) > kSceneNumberLimit) fail(fmt::format("{} is out of range: scene numbers lie in [-{:g}, {:g}]", v, kSceneNumberLimit, kSceneNumberLimit));
        return v;
    }
    double positive() const {
        const double v = number();
        if (!(v > 0.0)) fail(fmt::format("must be > 0, got {}", v));
        return v;
    }
    double non_negative() const {
        const double v = number();
        if (v < 0.0) fail(fmt::format("must be >= 0, got {}", v));
        return v;
    }
    int integer(int lo, int hi) const {
        const double v = number();
        if (v != std::floor(v) || v < lo || v > hi) fail(fmt::format("must be an integer in [{}, {}], got {}", lo, hi, v));
        return static_cast<int>(v);
    }
    template <std::size_t N>
    std::array<double, N> numbers() const {
        if (array_size() != N) fail(fmt::format("expected an array of {} numbers, got {} elements", N, value_.size()));
        std::array<double, N> out{};
        for (std::size_t i = 0; i < N; ++i) out[i] = at(i).number();
        return out;
    }
    glm::dvec3 vec3() const {
        const auto a = numbers<3>();
        return {a[0], a[1], a[2]};
    }
    glm::dvec3 positive_vec3() const {
        const glm::dvec3 v = vec3();
        for (int i = 0; i < 3; ++i)
            if (!(v[i] > 0.0)) at(static_cast<std::size_t>(i)).fail(fmt::format("must be > 0, got {}", v[i]));
        return v;
    }
    glm::dvec3 nonzero_vec3() const {
        const glm::dvec3 v = vec3();
        if (glm::length(v) == 0.0) fail("must not be the zero vector");
        return v;
    }
    // Unit quaternion [x, y, z, w]; within 1e-5 of unit length, then normalised.
    glm::dquat quaternion() const {
        const auto a = numbers<4>();
        const glm::dquat q(a[3], a[0], a[1], a[2]);
        const double n = glm::length(q);
        if (std::abs(n - 1.0) > 1e-5) fail(fmt::format("not a unit quaternion [x, y, z, w]: its norm is {}", n));
        // Normalised unless already unit to rounding, so that writing and reading back is exact.
        return std::abs(n - 1.0) <= 4e-16 ? q : q / n;
    }

private:
    std::string type_name() const { return value_.is_null() ? "null" : value_.type_name(); }
    const json& value_;
    std::string path_;
    std::string_view origin_;
};

}  // namespace sdfbrick::detail
