// Small statistics shared by the reports.
#pragma once

#include <algorithm>
#include <vector>

namespace sdfbrick {

// Median of v (mean of the two middle values for an even count); 0 for an empty v.
inline double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

}  // namespace sdfbrick
