// The one repeat loop of the run loop (inside pipeline/): warm-up passes, then captured ones, each a
// Pass; the captures, their statistics and digests gathered into a Run. A lane's run and a split run
// both go through it.
#pragma once

#include <chrono>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "pipeline/run.h"

namespace sdfbrick::pipeline::detail {

using Clock = std::chrono::steady_clock;

inline double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// Runs fn and adds its wall time to ms.
template <class Fn>
auto timed(double& ms, Fn&& fn) {
    struct Add {
        double& ms;
        Clock::time_point start = Clock::now();
        ~Add() { ms += ms_since(start); }
    } add{ms};
    return fn();
}

// What one pass produced.
struct Pass {
    render::SceneBricks bricks;
    std::optional<render::TraceResult> trace;
    std::string brick_digest, list_digest, trace_digest;
    double construct_wall = 0.0, bvh_wall = 0.0, trace_wall = 0.0, digest_wall = 0.0;
    measure::Capture capture;  // the pass's launches (every lane's, in a split)
};

// Runs warmup + repeat passes, pass(last) each, and keeps the captured ones. Before each pass the
// last pass's bricks and image go, so that the pass takes their memory again.
template <class PassFn>
Run repeat_passes(int warmup, int repeat, PassFn&& pass) {
    if (warmup < 0 || repeat < 1) throw std::invalid_argument("pipeline run: warmup >= 0 and repeat >= 1");
    Run out;
    std::vector<double> build_ms, bvh_ms, trace_ms, wall_ms, construct_wall, bvh_wall, trace_wall, digest_wall;
    std::uint64_t bricks = 0;
    for (int i = 0; i < warmup + repeat; ++i) {
        const auto start = Clock::now();
        out.bricks = {};
        out.trace.reset();
        Pass p = pass(i + 1 == warmup + repeat);
        if (i < warmup) continue;
        wall_ms.push_back(ms_since(start));
        out.captures.push_back(std::move(p.capture));
        build_ms.push_back(p.bricks.build_ms);
        bvh_ms.push_back(p.bricks.bvh.device_ms);
        trace_ms.push_back(p.trace ? p.trace->trace_ms : 0.0);
        construct_wall.push_back(p.construct_wall);
        bvh_wall.push_back(p.bvh_wall);
        trace_wall.push_back(p.trace_wall);
        digest_wall.push_back(p.digest_wall);
        if (out.captures.size() > 1 &&
            (p.bricks.bricks != bricks || p.brick_digest != out.brick_digest || p.list_digest != out.list_digest ||
             p.trace_digest != out.trace_digest))
            out.identical = false;
        bricks = p.bricks.bricks;
        out.brick_digest = std::move(p.brick_digest);
        out.list_digest = std::move(p.list_digest);
        out.trace_digest = std::move(p.trace_digest);
        out.bricks = std::move(p.bricks);
        out.trace = std::move(p.trace);
    }
    out.stages = measure::stage_stats(out.captures);
    out.total_ms = measure::total_stats(out.captures);
    out.build_ms = measure::spread_of(std::move(build_ms));
    out.bvh_ms = measure::spread_of(std::move(bvh_ms));
    out.trace_ms = measure::spread_of(std::move(trace_ms));
    out.wall_ms = measure::spread_of(std::move(wall_ms));
    out.construct_wall_ms = measure::spread_of(std::move(construct_wall));
    out.bvh_wall_ms = measure::spread_of(std::move(bvh_wall));
    out.trace_wall_ms = measure::spread_of(std::move(trace_wall));
    out.digest_wall_ms = measure::spread_of(std::move(digest_wall));
    return out;
}

}  // namespace sdfbrick::pipeline::detail
