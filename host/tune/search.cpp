#include "tune/search.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

#include <fmt/format.h>

#include "core/errors.h"

namespace sdfbrick::tune {

std::size_t Space::size() const {
    std::size_t n = dims.empty() ? 0 : 1;
    for (const auto& [name, values] : dims) n *= values.size();
    return n;
}

Config Space::at(std::size_t index) const {
    Config c;
    for (auto d = dims.rbegin(); d != dims.rend(); ++d) {
        c[d->first] = d->second[index % d->second.size()];
        index /= d->second.size();
    }
    return c;
}

std::string_view to_string(Strategy s) {
    switch (s) {
        case Strategy::full: return "full";
        case Strategy::random: return "random";
        case Strategy::anneal: return "anneal";
    }
    return "?";
}

Strategy strategy_from_string(std::string_view s, const Space& space, std::size_t budget) {
    if (s == "full") return Strategy::full;
    if (s == "random") return Strategy::random;
    if (s == "anneal") return Strategy::anneal;
    if (s == "auto") return space.size() <= budget ? Strategy::full : Strategy::anneal;
    throw SettingError("strategy", fmt::format("strategy must be auto, full, random or anneal, got \"{}\"", s));
}

std::size_t search_limit(const Space& space, Strategy strategy, std::size_t budget) {
    return strategy == Strategy::full ? space.size() : std::min(budget, space.size());
}

SearchResult search(const Space& space, Strategy strategy, std::size_t budget, std::uint64_t seed,
                    const std::function<double(const Config&)>& cost) {
    const std::size_t n = space.size(), limit = search_limit(space, strategy, budget);
    SearchResult r;
    r.best_cost = std::numeric_limits<double>::infinity();
    std::map<std::size_t, double> seen;
    const auto measure = [&](std::size_t i) {
        if (const auto it = seen.find(i); it != seen.end()) return it->second;
        const Config c = space.at(i);
        const double v = cost(c);
        seen[i] = v;
        r.evaluated.emplace_back(c, v);
        if (v < r.best_cost) {
            r.best_cost = v;
            r.best = c;
        }
        return v;
    };
    if (n == 0) return r;
    std::mt19937_64 rng(seed);
    if (strategy == Strategy::full) {
        for (std::size_t i = 0; i < limit; ++i) measure(i);
    } else if (strategy == Strategy::random) {
        std::vector<std::size_t> order(n);
        std::iota(order.begin(), order.end(), 0);
        std::shuffle(order.begin(), order.end(), rng);
        for (std::size_t k = 0; k < limit; ++k) measure(order[k]);
    } else {
        // Annealing over the grid: a neighbour moves one dimension one step. Temperature falls
        // geometrically from 10% of the first cost to 0.1% over the budget.
        std::uniform_int_distribution<std::size_t> any(0, n - 1);
        std::uniform_real_distribution<double> unit(0.0, 1.0);
        std::size_t current = any(rng);
        double current_cost = measure(current);
        const double t0 = std::isfinite(current_cost) ? 0.1 * current_cost : 1.0;
        for (std::size_t step = 0; seen.size() < limit && step < 20 * limit; ++step) {
            std::vector<std::size_t> radix;
            for (const auto& d : space.dims) radix.push_back(d.second.size());
            std::vector<std::size_t> digits(radix.size());
            std::size_t rest = current;
            for (std::size_t d = radix.size(); d-- > 0;) {
                digits[d] = rest % radix[d];
                rest /= radix[d];
            }
            const std::size_t dim = std::uniform_int_distribution<std::size_t>(0, radix.size() - 1)(rng);
            if (radix[dim] < 2) continue;
            const bool up = unit(rng) < 0.5;
            digits[dim] = up ? (digits[dim] + 1) % radix[dim] : (digits[dim] + radix[dim] - 1) % radix[dim];
            std::size_t next = 0;
            for (std::size_t d = 0; d < radix.size(); ++d) next = next * radix[d] + digits[d];
            const double next_cost = measure(next);
            const double t = t0 * std::pow(0.01, static_cast<double>(seen.size()) / static_cast<double>(limit));
            if (next_cost <= current_cost ||
                (std::isfinite(next_cost) && unit(rng) < std::exp(-(next_cost - current_cost) / t))) {
                current = next;
                current_cost = next_cost;
            }
        }
    }
    return r;
}

}  // namespace sdfbrick::tune
