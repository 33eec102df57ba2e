// wearscar watch: follows a force file the tribometer's software is still
// writing, analyses each cycle as it completes, raises alerts, and ends
// with the products `wearscar fuse` gives of the finished file.

#include <fmt/format.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>
#include <vector>

#include "commands.h"
#include "fuse_run.h"
#include "live_server.h"
#include "output.h"
#include "setting_flags.h"
#include "wearscar/force/block_joiner.h"
#include "wearscar/force/follow.h"
#include "wearscar/fusion/batch.h"
#include "wearscar/fusion/fuse.h"
#include "wearscar/fusion/live.h"
#include "wearscar/fusion/settings.h"
#include "wearscar/report/figures.h"

namespace wearscar::app {
namespace {

volatile std::sig_atomic_t interrupted = 0;
void OnInterrupt(int) { interrupted = 1; }

struct WatchArgs {
  std::string force_file, scan_file, out, name, on_alert;
  // A file per block: the blocks' folder (given as the force file), the
  // files' pattern, and what the watch follows (their joining).
  std::string folder, pattern;
  double poll_s = 0.1, idle_s = 60.0;
  int until_cycles = 0, every = 1, port = -1;
  fusion::LiveOptions live;
  bool no_figures = false;
  report::FigureFormats figure_formats;
  GivenSettings given;
};

std::string Now() {
  const std::time_t t = std::time(nullptr);
  char b[32];
  std::strftime(b, sizeof b, "%Y-%m-%dT%H:%M:%S", std::localtime(&t));
  return b;
}

// What the watch writes while the test runs: DIR/live/cycles.csv a row per
// cycle, DIR/events.jsonl a line per event (each flushed as written).
class LiveFiles {
 public:
  explicit LiveFiles(const std::string& out) : out_(out) {
    EnsureDirectory(out + "/live");
    cycles_.open(out + "/live/cycles.csv", std::ios::trunc);
    events_.open(out + "/events.jsonl", std::ios::trunc);
    if (!cycles_ || !events_)
      throw UsageError("watch: cannot write into " + out);
    WriteHeader();
  }
  // A new test in the file: the cycles so far move to
  // live/cycles.before-N.csv, and cycles.csv starts again.
  void Restart() {
    cycles_.close();
    ++restarts_;
    const std::string before =
        fmt::format("{}/live/cycles.before-{}.csv", out_, restarts_);
    std::rename((out_ + "/live/cycles.csv").c_str(), before.c_str());
    cycles_.open(out_ + "/live/cycles.csv", std::ios::trunc);
    WriteHeader();
  }
  void WriteHeader() {
    cycles_
        << "cycle,end_time_s,mu_hat,mu_hat_low,mu_hat_high,mu_mean,"
           "mu_energy,J,J_floor,J_excess,depth_mm,running_in,reported_unix_s\n";
    cycles_.flush();
  }
  void Cycle(const fusion::LiveCycle& c) {
    cycles_ << fmt::format(
        "{},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},"
        "{:.5f},{:.5f},{:.5f},{:.6f},{},{:.3f}\n",
        c.cycle,
        c.end_time_s,
        c.mu_hat,
        c.mu_low,
        c.mu_high,
        c.mu_mean,
        c.mu_energy,
        c.cost,
        c.cost_floor,
        c.cost_excess,
        c.depth_mm,
        c.running_in ? 1 : 0,
        std::chrono::duration<double>(
            std::chrono::system_clock::now().time_since_epoch())
            .count());
    cycles_.flush();
  }
  void Event(const fusion::LiveEvent& e, double wall_s) {
    nlohmann::json j = {{"time", Now()},
                        {"wall_s", wall_s},
                        {"kind", e.kind},
                        {"cycle", e.cycle},
                        {"test_time_s", e.time_s},
                        {"message", e.message},
                        {"good", e.good}};
    events_ << j.dump() << "\n";
    events_.flush();
  }

 private:
  std::string out_;
  int restarts_ = 0;
  std::ofstream cycles_, events_;
};

// Runs the user's command on an alert (/bin/sh -c) with the alert in its
// environment; it is not waited for (reaped as the watch goes on). The
// environment is made before fork: the child of a process with threads
// (the live page's) only calls execve.
void RunHook(const std::string& command, const fusion::LiveEvent& e) {
  if (command.empty()) return;
  std::vector<std::string> env;
  for (char** v = environ; *v != nullptr; ++v) {
    const std::string entry = *v;
    if (entry.rfind("WEARSCAR_ALERT=", 0) != 0 &&
        entry.rfind("WEARSCAR_CYCLE=", 0) != 0 &&
        entry.rfind("WEARSCAR_MESSAGE=", 0) != 0)
      env.push_back(entry);
  }
  env.push_back("WEARSCAR_ALERT=" + e.kind);
  env.push_back("WEARSCAR_CYCLE=" + std::to_string(e.cycle));
  env.push_back("WEARSCAR_MESSAGE=" + e.message);
  std::vector<char*> envp;
  for (std::string& v : env) envp.push_back(v.data());
  envp.push_back(nullptr);
  std::string sh = "/bin/sh", dash_c = "-c", cmd = command;
  char* argv[] = {sh.data(), dash_c.data(), cmd.data(), nullptr};
  const pid_t pid = fork();
  if (pid != 0) return;  // the watch, or fork failed
  execve("/bin/sh", argv, envp.data());
  _exit(127);
}

void SayCycle(const fusion::LiveCycle& c) {
  Say("  {:>6} {:>9.2f} {:>8.4f} {:>17} {:>8.4f} {:>7.3f} {:>7.3f} "
      "{:>9.4f}{}\n",
      c.cycle,
      c.end_time_s,
      c.mu_hat,
      fmt::format("{:.4f}-{:.4f}", c.mu_low, c.mu_high),
      c.mu_mean,
      c.cost,
      c.cost_excess,
      c.depth_mm,
      c.running_in ? "  running-in" : "");
  std::fflush(stdout);  // a line as each cycle completes, also into a pipe
}

void SayHeading() {
  Say("  {:>6} {:>9} {:>8} {:>17} {:>8} {:>7} {:>7} {:>9}\n",
      "cycle",
      "time_s",
      "mu_hat",
      "95%",
      "COF",
      "J",
      "excess",
      "depth_mm");
}

// The live phase: the file followed, each look's rows analysed, the
// cycles and events said and written.
class Watch {
 public:
  Watch(const WatchArgs& a,
        const fusion::TestSettings& settings,
        LiveServer* server)
      : a_(a),
        settings_(settings),
        server_(server),
        follower_(a.force_file, FollowOptionsOf(settings)),
        files_(a.out),
        start_(std::chrono::steady_clock::now()) {
    if (!a.pattern.empty())
      joiner_ = std::make_unique<force::BlockJoiner>(
          a.folder, a.pattern, a.force_file);
  }

  // Returns when the writer has been idle, the cycles asked for are done,
  // or the user interrupted: the bytes of the file taken (its complete
  // lines), or 0 when the writer stopped (the file is finished as it
  // stands).
  std::uintmax_t Run() {
    SayHeading();
    bool writer_stopped = false;
    while (!interrupted) {
      Look();
      if (follower_.offset() != last_offset_) {
        last_offset_ = follower_.offset();
        last_growth_ = Wall();
      } else if (Wall() - last_growth_ > a_.idle_s) {
        RaiseIdle();
        writer_stopped = true;
        break;
      }
      if (a_.until_cycles > 0 && live_ &&
          static_cast<int>(live_->cycles().size()) >= a_.until_cycles) {
        Say("{} cycles done (--until-cycles)\n", a_.until_cycles);
        break;
      }
      std::this_thread::sleep_for(std::chrono::duration<double>(a_.poll_s));
    }
    if (interrupted) Say("interrupted: the products of what was written\n");
    struct rusage usage {};
    getrusage(RUSAGE_SELF, &usage);
    const auto seconds = [](const timeval& t) {
      return static_cast<double>(t.tv_sec) + 1e-6 * t.tv_usec;
    };
    Say("followed {} cycles in {:.1f} s, {:.2f} s of CPU; peak memory {} "
        "MiB\n",
        live_ ? live_->cycles().size() : 0,
        Wall(),
        seconds(usage.ru_utime) + seconds(usage.ru_stime),
        usage.ru_maxrss / 1024);
    while (waitpid(-1, nullptr, 0) > 0) {
    }
    return writer_stopped ? 0 : follower_.offset();
  }

 private:
  static force::FollowOptions FollowOptionsOf(
      const fusion::TestSettings& settings) {
    force::FollowOptions fo;
    fo.read = settings.read_force;
    return fo;
  }
  double Wall() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                         start_)
        .count();
  }

  // One look at the file (with blocks: at the blocks, joined first).
  void Look() {
    if (joiner_) {
      const std::string note = joiner_->Update();
      if (!note.empty()) fmt::print(stderr, "wearscar: {}\n", note);
    }
    force::FollowedRows got = follower_.Poll(Wall() - last_growth_ > 1);
    while (waitpid(-1, nullptr, WNOHANG) > 0) {
    }
    if (!got.note.empty()) fmt::print(stderr, "wearscar: {}\n", got.note);
    if (got.restarted && live_) {
      live_->Restart(got.note, 0.0);
      files_.Restart();
    }
    if (!live_ && follower_.started()) {
      force::ForceRecord head;
      head.metadata = follower_.metadata();
      fusion::LiveOptions live = a_.live;
      // A test that ends after --until-cycles is planned that long.
      if (live.planned_cycles == 0) live.planned_cycles = a_.until_cycles;
      live_ = std::make_unique<fusion::LiveAnalysis>(
          fusion::WithStatedSpring(settings_.fuse, head), live);
    }
    if (!live_) return;
    if (got.rows.size() > 0) {
      for (const fusion::LiveCycle& c : live_->Add(std::move(got.rows))) {
        files_.Cycle(c);
        if (c.cycle % a_.every == 0 || c.cycle == 1) SayCycle(c);
      }
    }
    for (const fusion::LiveEvent& e : live_->TakeEvents()) Raise(e);
    if (server_) server_->Update(*live_);
  }

  void Raise(const fusion::LiveEvent& e) {
    fmt::print(stderr,
               "wearscar: {} cycle {}: {}\n",
               e.kind == "running-in" ? "note" : "ALERT",
               e.cycle,
               e.message);
    files_.Event(e, Wall());
    if (server_) server_->Event(e);
    RunHook(a_.on_alert, e);
  }

  void RaiseIdle() {
    fusion::LiveEvent e;
    e.kind = "idle";
    e.cycle =
        live_ && !live_->cycles().empty() ? live_->cycles().back().cycle : 0;
    e.message = fmt::format(
        "{} has not grown for {:g} s: the writer stopped; the watch ends",
        joiner_ ? fmt::format("no block of {} ({})", a_.folder, a_.pattern)
                : a_.force_file,
        a_.idle_s);
    Raise(e);
  }

  const WatchArgs& a_;
  const fusion::TestSettings& settings_;
  LiveServer* server_;
  force::ForceFollower follower_;
  std::unique_ptr<force::BlockJoiner> joiner_;
  std::unique_ptr<fusion::LiveAnalysis> live_;
  LiveFiles files_;
  std::chrono::steady_clock::time_point start_;
  double last_growth_ = 0;
  std::uintmax_t last_offset_ = 0;
};

// The file as it stood when the watch stopped: itself when nothing was
// written since, else its complete lines then, copied into DIR/live (a
// writer still writing would move the file under the analysis).
std::string FileAtStop(const WatchArgs& a, std::uintmax_t taken) {
  if (taken == 0) return a.force_file;
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(a.force_file, ec);
  if (ec || size <= taken) return a.force_file;
  const std::string copy =
      a.out + "/live/" +
      std::filesystem::path(a.force_file).filename().string() + ".at-stop";
  std::ifstream in(a.force_file, std::ios::binary);
  std::ofstream out(copy, std::ios::binary | std::ios::trunc);
  std::vector<char> block(std::size_t{1} << 20);
  for (std::uintmax_t left = taken; left > 0 && in;) {
    const auto n = static_cast<std::streamsize>(
        std::min<std::uintmax_t>(left, block.size()));
    in.read(block.data(), n);
    out.write(block.data(), in.gcount());
    left -= static_cast<std::uintmax_t>(in.gcount());
  }
  if (!out) throw UsageError("watch: cannot write " + copy);
  Say("{} is still being written: the products are of its {} bytes when the "
      "watch stopped, copied to {}\n",
      a.force_file,
      taken,
      copy);
  return copy;
}

// With --pattern, the force argument is the blocks' folder, and the watch
// follows their joining, DIR/live/<folder>.joined<the pattern's extension>.
void JoinBlocks(WatchArgs* a) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const bool folder = fs::is_directory(a->force_file, ec);
  if (a->pattern.empty()) {
    if (folder)
      throw UsageError("watch: " + a->force_file +
                       " is a folder: give --pattern for a file per block "
                       "(--pattern 'run_*.csv')");
    return;
  }
  if (!folder)
    throw UsageError("watch --pattern: " + a->force_file +
                     " is not a folder (the blocks' folder is expected)");
  a->folder = a->force_file;
  std::string ext = fs::path(a->pattern).extension().string();
  if (ext.find_first_of("*?[") != std::string::npos) ext.clear();
  // The folder's own name, also for "." or "run/" (an empty file name).
  fs::path where = fs::absolute(a->folder, ec).lexically_normal();
  if (where.filename().empty()) where = where.parent_path();
  const std::string stem = where.filename().string();
  EnsureDirectory(a->out + "/live");
  a->force_file = a->out + "/live/" + (stem.empty() ? "blocks" : stem) +
                  ".joined" + (ext.empty() ? ".txt" : ext);
  if (a->name.empty()) a->name = stem;
}

void RunWatch(WatchArgs a) {
  fusion::TestSettings settings =
      WithFlagNames([&] { return fusion::MakeTestSettings(a.given); });
  interrupted = 0;
  EnsureDirectory(a.out);
  JoinBlocks(&a);
  std::signal(SIGINT, OnInterrupt);
  std::signal(SIGTERM, OnInterrupt);
  std::unique_ptr<LiveServer> server;
  if (a.port >= 0) {
    server = std::make_unique<LiveServer>(a.port);
    fmt::print(stderr, "wearscar: the live page: {}\n", server->Address());
  }
  const std::uintmax_t taken = Watch(a, settings, server.get()).Run();
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  // The finished file as `wearscar fuse` analyses it.
  FuseArgs f;
  f.force_file = FileAtStop(a, taken);
  f.scan_file = a.scan_file;
  f.out = a.out;
  f.name = a.name.empty() ? fusion::SpecimenName(a.force_file) : a.name;
  f.no_figures = a.no_figures;
  f.figure_formats = a.figure_formats;
  f.given = a.given;
  RunFuse(f);
}

// The steady alert's options.
void AddSteadyOptions(CLI::App* cmd, fusion::LiveOptions* live) {
  cmd->add_option("--steady-cycles",
                  live->steady_cycles,
                  "Steady: mu-hat's trend and shift over this many cycles "
                  "(30)")
      ->check(CLI::Range(5, 100000));
  cmd->add_option(
         "--steady-band", live->steady_band, "Steady: both within this (0.005)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--steady-hold",
                  live->steady_hold_cycles,
                  "Steady: said once both have held on this many successive "
                  "cycles (5; at most --steady-cycles)")
      ->check(CLI::Range(1, 100000));
  cmd->add_option("--planned-cycles",
                  live->planned_cycles,
                  "Steady: the test's planned length; the last cycles' trend "
                  "over the cycles left must stay within the band (default: "
                  "--until-cycles; without either it is not checked)")
      ->check(CLI::Range(0, 100000000));
}

}  // namespace

void AddWatchCommand(CLI::App& app) {
  auto args = std::make_shared<WatchArgs>();
  auto* cmd = app.add_subcommand(
      "watch",
      "Follow a force file while the test runs: mu-hat with k from P per "
      "cycle as each completes, alerts (steady, verdict, depth, idle), a live "
      "page; at the end the products of `wearscar fuse` on the finished file");
  cmd->add_option("force,--force",
                  args->force_file,
                  "The force export being written (positional or --force); "
                  "with --pattern, the folder of its blocks")
      ->required();
  cmd->add_option("--pattern",
                  args->pattern,
                  "A file per block: the folder's files matching this pattern "
                  "('run_*.csv'), in natural order (run_2 before run_10), "
                  "joined as they are written; a block is finished once a "
                  "later one exists");
  cmd->add_option("--scan",
                  args->scan_file,
                  "Height map of the worn track, for the final products");
  cmd->add_option("-o,--out", args->out, "Directory for the results")
      ->required();
  cmd->add_option("--name", args->name, "Specimen name in the outputs");
  cmd->add_option("--poll", args->poll_s, "Seconds between looks (0.1)")
      ->check(CLI::Range(0.01, 60.0));
  cmd->add_option("--idle",
                  args->idle_s,
                  "The writer has stopped when the file has not grown for "
                  "this many seconds: an alert, and the end (60)")
      ->check(CLI::Range(0.1, 1e6));
  cmd->add_option(
         "--until-cycles", args->until_cycles, "End after this many cycles")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--every", args->every, "Print every N-th cycle (1)")
      ->check(CLI::PositiveNumber);
  AddSteadyOptions(cmd, &args->live);
  cmd->add_option("--max-depth",
                  args->live.max_depth_mm,
                  "Alert when the track's depth from the spring (P/S peak to "
                  "valley) exceeds this, mm")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--on-alert",
                  args->on_alert,
                  "Command run (sh -c) on each alert, with WEARSCAR_ALERT, "
                  "WEARSCAR_CYCLE and WEARSCAR_MESSAGE in its environment");
  cmd->add_option("--port",
                  args->port,
                  "Serve the live page on 127.0.0.1 at this port (0: any "
                  "free one; default: no page)")
      ->check(CLI::Range(0, 65535));
  AddTestCommandOptions(cmd,
                        &args->no_figures,
                        &args->figure_formats,
                        fusion::kFuseSettings,
                        /*break_lock=*/false,
                        &args->given);
  cmd->footer(
      "Examples:\n"
      "  wearscar watch running.csv -o out/T7 --port 0\n"
      "  wearscar watch exports/T7 --pattern 'T7_block*.csv' -o out/T7\n"
      "  wearscar watch running.csv -o out/T7 --max-depth 0.3 "
      "--on-alert 'notify-send \"$WEARSCAR_MESSAGE\"'");
  cmd->callback([args] { RunWatch(*args); });
}

}  // namespace wearscar::app
