// `sdfbrick play`: the frame loop. Plays a scene's animation for --frames frames (--fps or --dt, from
// --from), rebuilding what changes each frame, tracing it, optionally writing every frame's picture
// (--out frames/%04d.png) on a writer thread so that the loop does not wait for the encoder, and
// reports per-frame wall and device times and the run's percentiles (docs/frames.md).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <exception>
#include <filesystem>
#include <memory>
#include <mutex>
#include <thread>

#include <fmt/format.h>

#include "cli/build_flags.h"
#include "cli/commands.h"
#include "core/errors.h"
#include "core/files.h"
#include "core/quote.h"
#include "image/image.h"
#include "pipeline/command_report.h"
#include "pipeline/play.h"
#include "scene/edit_log.h"
#include "scene/scene_json.h"
#include "scene/to_device.h"
#include "tune/apply.h"

namespace sdfbrick::cli {

namespace {

struct PlayOptions {
    std::string file;
    int frames = 60;
    std::optional<double> fps, dt, from;
    BuildFlags flags;
    TraceFlags tracing;
    std::optional<std::string> out, json, edits;
    std::string work = "trace";
    bool digests = false;
};

// A frame file pattern: one printf-style integer field (%d or %0Nd, N <= 9) for the frame number;
// "%%" is a percent sign.
class FramePattern {
public:
    explicit FramePattern(const std::string& pattern) {
        int fields = 0;
        bool bad = false;
        for (std::size_t i = 0; i < pattern.size() && !bad; ++i) {
            if (pattern[i] != '%') {
                current().push_back(pattern[i]);
            } else if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
                current().push_back('%');
                ++i;
            } else {
                std::size_t j = i + 1;
                int width = 0;
                if (j < pattern.size() && pattern[j] == '0') ++j;
                if (j < pattern.size() && pattern[j] >= '1' && pattern[j] <= '9') width = pattern[j++] - '0';
                bad = j >= pattern.size() || pattern[j] != 'd' || ++fields > 1;
                width_ = width;
                i = j;
            }
        }
        if (bad || fields != 1)
            throw InputError(fmt::format("--out: the pattern must hold one frame field (%d or %04d) and %% for a "
                                         "percent sign, got {}",
                                         quoted_input(pattern)));
    }
    std::filesystem::path at(int frame) const {
        return parts_[0] + (width_ > 0 ? fmt::format("{:0{}}", frame, width_) : std::to_string(frame)) + parts_[1];
    }

private:
    std::string& current() { return parts_[field_seen() ? 1 : 0]; }
    bool field_seen() const { return width_ >= 0; }
    std::string parts_[2];
    int width_ = -1;
};

// Writes the frames' pictures on writer threads (each picture encoded and written whole, flushed to
// disk, as every output is), at most kDepth per thread queued: the loop waits only when the writers
// are that far behind. The first failure is rethrown by finish().
class FrameWriter {
public:
    static constexpr std::size_t kDepth = 2;
    FrameWriter(std::string mode, FramePattern pattern) : mode_(std::move(mode)), pattern_(std::move(pattern)) {
        const unsigned n = std::clamp(std::thread::hardware_concurrency() / 2, 1u, 4u);
        for (unsigned i = 0; i < n; ++i) threads_.emplace_back([this] { loop(); });
    }
    ~FrameWriter() { stop(); }
    FrameWriter(const FrameWriter&) = delete;
    FrameWriter& operator=(const FrameWriter&) = delete;

    void push(int frame, render::TraceResult&& trace) {
        std::unique_lock lock(mutex_);
        room_.wait(lock, [&] { return queue_.size() < kDepth * threads_.size() || error_; });
        if (error_) return;
        queue_.push_back({frame, std::move(trace)});
        work_.notify_one();
    }
    void finish() {
        stop();
        if (error_) std::rethrow_exception(error_);
    }

private:
    struct Item {
        int frame;
        render::TraceResult trace;
    };
    void stop() {
        {
            std::lock_guard lock(mutex_);
            done_ = true;
        }
        work_.notify_all();
        for (std::thread& t : threads_)
            if (t.joinable()) t.join();
    }
    void loop() {
        for (;;) {
            std::unique_lock lock(mutex_);
            work_.wait(lock, [&] { return !queue_.empty() || done_; });
            if (queue_.empty()) return;
            Item item = std::move(queue_.front());
            queue_.pop_front();
            lock.unlock();
            room_.notify_one();
            try {
                const std::filesystem::path path = pattern_.at(item.frame);
                write_all({image_output(pipeline::mode_picture(mode_, item.trace.buffer, item.trace.colour, false), path)});
            } catch (...) {
                lock.lock();
                if (!error_) error_ = std::current_exception();
                queue_.clear();
                lock.unlock();
                room_.notify_all();
            }
        }
    }
    std::string mode_;
    FramePattern pattern_;
    std::mutex mutex_;
    std::condition_variable work_, room_;
    std::deque<Item> queue_;
    bool done_ = false;
    std::exception_ptr error_;
    std::vector<std::thread> threads_;
};

pipeline::PlaySpec play_spec(const PlayOptions& o, double scene_time) {
    if (o.frames < 1 || o.frames > pipeline::kMaxFrames)
        throw InputError(fmt::format("--frames must lie in 1 .. {}, got {}", pipeline::kMaxFrames, o.frames));
    if (o.fps && o.dt) throw InputError("--fps and --dt exclude each other");
    if (o.fps && !(*o.fps > 0.0)) throw InputError(fmt::format("--fps must be > 0, got {}", *o.fps));
    if (o.dt && !(*o.dt > 0.0)) throw InputError(fmt::format("--dt must be > 0, got {}", *o.dt));
    pipeline::PlaySpec spec;
    spec.frames = o.frames;
    spec.from = o.from.value_or(scene_time);
    spec.dt = o.dt.value_or(1.0 / o.fps.value_or(60.0));
    spec.digests = o.digests;
    if (o.work == "construct") spec.work = pipeline::Work::construct;
    else if (o.work == "bvh") spec.work = pipeline::Work::bvh;
    else if (o.work != "trace") throw InputError(fmt::format("--work must be construct, bvh or trace, got {}", quoted_input(o.work)));
    if (o.out && spec.work != pipeline::Work::trace) throw InputError("--out needs --work trace: the pictures are the trace's");
    return spec;
}

void check_frame_outputs(const PlayOptions& o, const std::optional<FramePattern>& pattern) {
    std::vector<std::filesystem::path> paths;
    if (pattern)
        for (int i = 0; i < o.frames; ++i) paths.push_back(pattern->at(i));
    if (o.json) paths.push_back(*o.json);
    check_output_paths(paths);
}

void run_play(PlayOptions o, const GlobalOptions& global) {
    apply_global_options(global, true);
    const construct::BuildSettings settings = o.flags.resolve();
    const render::TraceSettings trace = o.tracing.resolve();
    const std::string& mode = o.tracing.mode;
    std::optional<FramePattern> pattern;
    if (o.out) pattern.emplace(*o.out);

    const Scene scene = load_scene_warned(o.file);
    pipeline::PlaySpec spec = play_spec(o, scene.time);
    std::optional<EditLog> log;
    if (o.edits) {
        log = load_edit_log(*o.edits, scene);
        spec.edits = &*log;
        if (!log->ops.empty() && log->ops.back().frame >= spec.frames)
            throw InputError(fmt::format("{}:{}: /frame: frame {} is not played (--frames {})", *o.edits,
                                         log->ops.back().line, log->ops.back().frame, spec.frames));
    }
    check_frame_outputs(o, pattern);
    const std::unique_ptr<RunDevices> devices = open_run_devices(global);
    if (devices->placement == pipeline::Placement::replicate && devices->set.size() > 1)
        throw InputError("--devices replicate: play runs one device, or several with --devices split");
    const TuningChoice tuning = open_tuning(global);
    tune::Given given = o.flags.given();
    given.trace_group = o.tracing.group_given();
    given.trace_registers = o.tracing.registers_given();

    std::optional<FrameWriter> writer;
    if (pattern) {
        writer.emplace(mode, *pattern);
        spec.on_image = [&writer](int frame, render::TraceResult&& t) { writer->push(frame, std::move(t)); };
    }
    const bool terminal = isatty(STDERR_FILENO) != 0;
    const auto start = std::chrono::steady_clock::now();
    spec.progress = [terminal, start](int done, int total) {
        if (!terminal) return;
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::fprintf(stderr, "\r[play] %d/%d frames, elapsed %s, ETA %s", done, total, clock_text(s).c_str(),
                     clock_text(s / done * (total - done)).c_str());
        if (done == total) std::fputc('\n', stderr);
    };
    const pipeline::Placement placement =
        devices->placement == pipeline::Placement::split ? pipeline::Placement::split : pipeline::Placement::whole;
    const pipeline::PlayRun run =
        pipeline::play(devices->executor, scene, tune::settings_for(settings, trace, tuning.get(), given), placement, spec);
    if (writer) writer->finish();

    const pipeline::PlayRequest request{o.file,           scene.name, mode, trace, o.dt ? 0.0 : 1.0 / spec.dt,
                                        o.out.value_or(""), o.edits.value_or(""), spec.work};
    if (o.json) write_all({text_output(*o.json, format_json(pipeline::to_json(request, run)))});
    std::fputs(pipeline::to_text(request, run).c_str(), stdout);
}

}  // namespace

void add_play_command(CLI::App& app, const GlobalOptions& global) {
    auto o = std::make_shared<PlayOptions>();
    auto* cmd = app.add_subcommand("play", "Play a scene's animation: each frame rebuilt where it changed, its BVH "
                                           "built and traced; per-frame wall and device times");
    cmd->add_option("file", o->file, "scene file (JSON)")->required();
    cmd->add_option("--frames", o->frames, fmt::format("frames to play (1..{})", pipeline::kMaxFrames))->capture_default_str();
    cmd->add_option("--fps", o->fps, "frames per second: the time step and the frame budget (default 60)")
        ->check(finite_number());
    cmd->add_option("--dt", o->dt, "time step in seconds instead of --fps (the budget is the step)")->check(finite_number());
    cmd->add_option("--from", o->from, "the first frame's time in seconds (default: the scene's)")->check(finite_number());
    o->flags.add_to(cmd);
    o->tracing.add_to(cmd);
    cmd->add_option("--out", o->out, "write every frame's picture: a pattern with one frame field, e.g. frames/%04d.png");
    cmd->add_option("--json", o->json, "write the report (every frame and the summary) as JSON");
    cmd->add_option("--edits", o->edits, "an edit log (JSON lines: append, remove or replace edits at given frames)");
    cmd->add_option("--work", o->work, "how far each frame goes: construct, bvh or trace")->capture_default_str();
    cmd->add_flag("--digests", o->digests, "each frame's brick and image digests, computed on the device");
    cmd->callback([o, &global] { run_play(*o, global); });
}

}  // namespace sdfbrick::cli
