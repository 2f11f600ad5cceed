// Small statistics shared by the reports.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace sdfbrick {

// Median of v (mean of the two middle values for an even count); 0 for an empty v.
inline double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

// Nearest rank: v[ceil(p n / 100)] (1-based) of the sorted values, v[1] for rank 0; 0 when empty.
inline double percentile(std::vector<double> v, double p) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const double rank = std::ceil(p / 100.0 * static_cast<double>(v.size()));
    const std::size_t r = rank < 1.0 ? 1 : std::min(static_cast<std::size_t>(rank), v.size());
    return v[r - 1];
}

}  // namespace sdfbrick
