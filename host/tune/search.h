// Search strategies of `sdfbrick tune` over a small grid of integer launch parameters: a full search
// for small spaces, random sampling or simulated annealing for large ones (as Kernel Tuner offers).
// Each configuration is measured once (cost: the minimum over its repeats); an infinite cost marks a
// configuration the device cannot run.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace sdfbrick::tune {

using Config = std::map<std::string, int>;

struct Space {
    std::vector<std::pair<std::string, std::vector<int>>> dims;  // name -> candidate values
    std::size_t size() const;
    Config at(std::size_t index) const;  // mixed-radix index, the last dimension fastest
};

enum class Strategy { full, random, anneal };
std::string_view to_string(Strategy s);
// "full", "random", "anneal", or "auto" (full when the space fits the budget, else anneal). Throws
// InputError otherwise.
Strategy strategy_from_string(std::string_view s, const Space& space, std::size_t budget);

struct SearchResult {
    Config best;
    double best_cost = 0.0;  // +infinity when no configuration could run
    std::vector<std::pair<Config, double>> evaluated;  // in the order measured
};

// The most configurations `search` measures: all of the space's for full, else at most the budget
// (anneal may stop short of it).
std::size_t search_limit(const Space& space, Strategy strategy, std::size_t budget);

// Measures at most search_limit distinct configurations. seed makes random and anneal repeatable.
SearchResult search(const Space& space, Strategy strategy, std::size_t budget, std::uint64_t seed,
                    const std::function<double(const Config&)>& cost);

}  // namespace sdfbrick::tune
