// The frame loop and edit logs: after every operation of a long random log the frame's bricks, edit
// lists and image equal a fresh build of the edited scene, bit for bit; a geometry the log does not
// touch keeps its bricks; logs that name what is not there are refused by line and field.
#include <gtest/gtest.h>

#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "core/rng.h"
#include "pipeline/executor.h"
#include "pipeline/play.h"
#include "scene/edit_log.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace sdfbrick {
namespace {

pipeline::Executor& executor() {
    static pipeline::Executor e(test::device());
    return e;
}

pipeline::SettingsFor settings() {
    return [](const ocl::DeviceInfo&) {
        pipeline::LaneSettings s;
        s.build.leaf_size = 0.125;
        s.trace.width = 48;
        s.trace.height = 32;
        return s;
    };
}

// Two geometries: "clay", which the log sculpts, and "stand", which it never touches. Two specks at
// clay's corners fix its domain, and its torus has the largest blend, so that strokes inside move
// neither the domain nor the saturation: most operations are rebuilt only where they reach.
Scene base_scene() {
    return parse_scene(R"({"camera": {"orbit": {"target": [0, 0, 0], "distance": 4.0}},
        "geometries": [
          {"name": "stand", "edits": [{"primitive": "box", "half_extents": [1.2, 0.1, 1.2], "position": [0, -1.2, 0]}]},
          {"name": "clay", "edits": [{"primitive": "sphere", "radius": 0.8},
                                     {"primitive": "torus", "major_radius": 0.7, "minor_radius": 0.12, "blend": 0.2},
                                     {"primitive": "sphere", "radius": 0.05, "position": [-1.45, -1.45, -1.45]},
                                     {"primitive": "sphere", "radius": 0.05, "position": [1.45, 1.45, 1.45]}]}]})",
                       "<test>");
}

nlohmann::json random_edit(Rng& rng) {
    const glm::dvec3 p = rng.unit_vector() * rng.uniform(0.6, 1.0);
    nlohmann::json e{{"position", {p.x, p.y, p.z}}, {"blend", rng.uniform(0.0, 0.15)}};
    if (rng.uniform() < 0.5) {
        e["primitive"] = "sphere";
        e["radius"] = rng.uniform(0.05, 0.3);
    } else {
        const glm::dquat q = rng.rotation();
        e["primitive"] = "capsule";
        e["half_length"] = rng.uniform(0.0, 0.3);
        e["radius"] = rng.uniform(0.03, 0.15);
        e["rotation"] = {q.x, q.y, q.z, q.w};
    }
    if (rng.uniform() < 0.3) e["op"] = "subtract";
    return e;
}

// `ops` operations on "clay" (its specks never removed or replaced), one per frame but every fifth
// frame three: strokes appended, edits removed and replaced at random.
std::string random_log(std::uint64_t seed, int ops) {
    Rng rng(seed);
    std::size_t size = 4;
    std::string text;
    for (int i = 0, frame = 0; i < ops; ++i) {
        frame += i % 5 == 1 || i % 5 == 2 ? 0 : i > 0 ? 1 : 0;
        nlohmann::json op{{"frame", frame}, {"geometry", "clay"}};
        const auto some = [&] { return std::size_t{4} + static_cast<std::size_t>(rng.uniform() * static_cast<double>(size - 4)); };
        const double r = rng.uniform();
        if (r < 0.45 || size < 5) {
            nlohmann::json edits = nlohmann::json::array();
            const int n = 1 + static_cast<int>(rng.uniform() * 4);
            for (int i = 0; i < n; ++i) edits.push_back(random_edit(rng));
            op["op"] = "append";
            op["edits"] = edits;
            size += edits.size();
        } else if (r < 0.7) {
            op["op"] = "remove";
            op["index"] = some();
            --size;
        } else {
            op["op"] = "replace";
            op["index"] = some();
            op["edit"] = random_edit(rng);
        }
        text += op.dump() + "\n";
    }
    return text;
}

// Every state of a random log of 60 operations (in 36 frames): the frame equals a fresh build of the
// edited scene (bricks, edit lists, image); the stand is built once, and most frames rebuild clay
// only where the operations reach (the rest fall back to a whole build: a stroke that moves its
// domain).
TEST(PipelinePlay, EveryStateOfARandomLogEqualsAFullRebuild) {
    const Scene scene = base_scene();
    const EditLog log = parse_edit_log(random_log(7, 60), "random.jsonl", scene);
    pipeline::PlaySpec spec;
    spec.frames = log.ops.back().frame + 1;
    spec.digests = true;
    spec.edits = &log;
    const pipeline::PlayRun run = pipeline::play(executor(), scene, settings(), pipeline::Placement::whole, spec);
    ASSERT_EQ(run.frames.size(), 36u);

    Scene state = scene;
    pipeline::Job fresh;
    fresh.settings = settings();
    std::size_t next = 0, spliced = 0, fewer = 0;
    for (const pipeline::FrameRecord& f : run.frames) {
        const std::size_t first = next;
        for (; next < log.ops.size() && log.ops[next].frame == f.index; ++next) apply(state, log.ops[next]);
        EXPECT_EQ(f.operations, next - first);
        EXPECT_EQ(f.geometries_rebuilt, f.index == 0 ? 2u : 1u) << f.index;
        spliced += f.geometries_spliced;
        if (f.geometries_spliced > 0 && f.bricks_rebuilt < f.bricks) ++fewer;
        pipeline::Executor other(test::device());  // nothing kept from the frames
        const pipeline::Execution e = other.run(scene_at(state, f.time), fresh);
        EXPECT_EQ(f.brick_digest, e.job().brick_digest) << "frame " << f.index;
        EXPECT_EQ(f.list_digest, e.job().list_digest) << "frame " << f.index;
        EXPECT_EQ(f.trace_digest, e.job().trace_digest) << "frame " << f.index;
        EXPECT_EQ(f.bricks, e.job().bricks.bricks) << "frame " << f.index;
    }
    EXPECT_GE(spliced, 20u);
    EXPECT_EQ(fewer, spliced) << "a spliced frame builds fewer bricks than a whole one";
    EXPECT_EQ(pipeline::summarise(run).edit_frames, 35u);
}

// Work::construct frames build only; a log frame past the frames played is refused.
TEST(PipelinePlay, ConstructOnlyFramesAndUnplayedOperations) {
    const Scene scene = base_scene();
    const EditLog log = parse_edit_log(random_log(3, 6), "random.jsonl", scene);  // frames 0, 0, 0, 1, 2, 3
    pipeline::PlaySpec spec;
    spec.frames = 4;
    spec.work = pipeline::Work::construct;
    spec.digests = true;
    spec.edits = &log;
    const pipeline::PlayRun run = pipeline::play(executor(), scene, settings(), pipeline::Placement::whole, spec);
    for (const pipeline::FrameRecord& f : run.frames) {
        EXPECT_TRUE(f.trace_digest.empty());
        EXPECT_FALSE(f.brick_digest.empty());
        EXPECT_EQ(f.trace_ms + f.bvh_ms, 0.0);
    }
    spec.frames = 3;
    const std::string message = test::input_error_of([&] {
        pipeline::play(executor(), scene, settings(), pipeline::Placement::whole, spec);
    });
    EXPECT_NE(message.find("random.jsonl:6: /frame: frame 3 is not played"), std::string::npos) << message;
}

// Each refusal names the line and the field; the operations before a bad index are counted.
TEST(SceneEditLog, RefusalsNameTheLineAndTheField) {
    const Scene scene = base_scene();
    const std::pair<std::string, std::string> cases[] = {
        {R"({"frame": 0, "op": "remove", "geometry": "clay", "index": 4})", "log:1: /index: no edit 4 in geometry \"clay\" (it has 4 there)"},
        {R"({"frame": 0, "op": "append", "geometry": "rock", "edit": {"primitive": "sphere", "radius": 1}})", "log:1: /geometry: no geometry named \"rock\""},
        {R"({"frame": 0, "op": "append", "geometry": 5, "edit": {"primitive": "sphere", "radius": 1}})", "log:1: /geometry: no geometry 5 (the scene has 2)"},
        {R"({"frame": 0, "op": "move", "geometry": 0, "index": 0})", "log:1: /op: unknown operation \"move\""},
        {R"({"frame": -1, "op": "remove", "geometry": 1, "index": 0})", "log:1: /frame: must be an integer"},
        {R"({"frame": 0, "op": "append", "geometry": 1, "edit": {"primitive": "sphere", "radius": -1}})", "log:1: /edit/radius: must be > 0"},
        {R"({"frame": 0, "op": "append", "geometry": 1, "edits": [{"primitive": "blob"}]})", "log:1: /edits/0/primitive"},
        {R"({"frame": 0, "op": "replace", "geometry": 1, "index": 0})", "log:1: /edit: needs exactly one of"},
        {R"({"frame": 0, "op": "remove", "geometry": 0, "index": 0})", "removes the last edit of geometry \"stand\""},
        {R"({"frame": 0, "op": "append", "geometry": 1, "edit": {"primitive": "mesh", "file": "x.obj"}})", "a mesh or level-set edit cannot be added here"},
        {"{\"frame\": 0, \"op\": \"remove\", \"geometry\": 1, \"index\": 0}\n\n{\"frame\": 0, \"op\": \"remove\", \"geometry\": 1, \"index\": 3}",
         "log:3: /index: no edit 3 in geometry \"clay\" (it has 3 there)"},
        {"{\"frame\": 2, \"op\": \"remove\", \"geometry\": 1, \"index\": 0}\n{\"frame\": 1, \"op\": \"remove\", \"geometry\": 1, \"index\": 0}",
         "log:2: /frame: frames must not decrease: 1 after 2"},
        {R"({"frame": 0, "op": "remove", "geometry": 1, "index": 0, "extra": 1})", "log:1: /extra: unknown field"},
        {R"({"frame": 0, "op": "remove", "geometry": 1, "index": 0)", "log:1"},
        {"[1, 2]", "log:1: expected an operation object"},
        {"{\"frame\": 0, \"f\x7f\": 1}", "log:1: /f\\x7f: unknown field"},  // a key's bytes echoed escaped
    };
    for (const auto& [text, message] : cases) {
        const std::string got = test::input_error_of([&] { parse_edit_log(text, "log", scene); });
        EXPECT_NE(got.find(message), std::string::npos) << text << "\n  got: " << got;
        for (char c : got) EXPECT_TRUE(c >= 0x20 && c < 0x7f) << got;
    }
    // A valid log: operations in order, edits in the scene's terms.
    const EditLog ok = parse_edit_log(
        "{\"frame\": 1, \"op\": \"append\", \"geometry\": \"clay\", \"edits\": [{\"primitive\": \"sphere\", \"radius\": 0.2}]}\n"
        "{\"frame\": 1, \"op\": \"replace\", \"geometry\": 1, \"index\": 2, \"edit\": {\"primitive\": \"sphere\", \"radius\": 0.3}}\n"
        "{\"frame\": 4, \"op\": \"remove\", \"geometry\": \"clay\", \"index\": 0}\n",
        "log", scene);
    ASSERT_EQ(ok.ops.size(), 3u);
    Scene s = scene;
    for (const EditOp& op : ok.ops) apply(s, op);
    ASSERT_EQ(s.geometries[1].edits.size(), 4u);
    EXPECT_EQ(s.geometries[1].edits[1].params[0], 0.3);
    EXPECT_EQ(s.geometries[1].edits[3].params[0], 0.2);
    EXPECT_EQ(s.geometries[1].edits[0].primitive, Primitive::Torus);
    EXPECT_EQ(ok.ops[2].line, 3u);
}

}  // namespace
}  // namespace sdfbrick
