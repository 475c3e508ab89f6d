// Batch runs: input expansion and names, the summary (built from the folders, RFC 4180), the runner
// (a broken input never stops the others, resume, --force, --retry-errors, options check, lock), and the
// CLI killed in the middle of a batch.
#include "spheremap/pipeline/batch.hpp"

#include <gtest/gtest.h>

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>
#include <sys/resource.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <random>
#include <sstream>
#include <thread>

#include <fmt/format.h>

#include "../test_support.hpp"
#include "spheremap/error.hpp"
#include "spheremap/io/ply.hpp"
#include "spheremap/shapes/shapes.hpp"

extern char** environ;

namespace spheremap {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

using testing_support::slurp;
using testing_support::write_text;

// A minimal RFC 4180 reader (quoted fields with doubled quotes, commas and line breaks inside).
std::vector<std::vector<std::string>> parse_csv(const std::string& text) {
  std::vector<std::vector<std::string>> rows(1);
  std::string field;
  bool quoted = false, was_quoted = false;
  for (std::size_t k = 0; k < text.size(); ++k) {
    const char c = text[k];
    if (quoted) {
      if (c == '"' && k + 1 < text.size() && text[k + 1] == '"')
        field += '"', ++k;
      else if (c == '"')
        quoted = false;
      else
        field += c;
    } else if (c == '"') {
      EXPECT_TRUE(field.empty()) << "a quote inside an unquoted field";
      quoted = was_quoted = true;
    } else if (c == ',') {
      rows.back().push_back(field), field.clear(), was_quoted = false;
    } else if (c == '\n') {
      rows.back().push_back(field), field.clear(), was_quoted = false;
      rows.emplace_back();
    } else {
      field += c;
    }
  }
  EXPECT_FALSE(quoted) << "unterminated quoted field";
  EXPECT_TRUE(field.empty() && rows.back().empty()) << "the last line has no line end";
  rows.pop_back();
  (void)was_quoted;
  return rows;
}

// Measurements (timings, peak memory) differ between runs; everything else must not.
bool is_timing(const std::string& column) { return column.rfind("seconds_", 0) == 0 || column == "peak_rss_mb"; }

// summary.csv and summary.jsonl with the measured timings blanked: what must be identical between an
// interrupted-and-resumed batch and an uninterrupted one.
std::string csv_without_timings(const std::string& text) {
  const auto rows = parse_csv(text);
  std::string out;
  for (const auto& row : rows) {
    EXPECT_EQ(row.size(), rows.front().size());
    for (std::size_t k = 0; k < row.size(); ++k)
      out += (k ? "|" : "") + (is_timing(rows.front()[k]) ? std::string("-") : row[k]);
    out += "\n";
  }
  return out;
}

std::string jsonl_without_timings(const std::string& text) {
  std::istringstream lines(text);
  std::string out;
  for (std::string line; std::getline(lines, line);) {
    Json row = Json::parse(line);
    for (auto& [key, value] : row.items())
      if (is_timing(key)) value = nullptr;
    out += row.dump() + "\n";
  }
  return out;
}

// Four atoms (PQR: radius column, no gemmi): a small molecular surface.
constexpr const char* kTinyPqr =
    "ATOM      1  N   GLY A   1       0.000   0.000   0.000  0.0000 1.5500\n"
    "ATOM      2  CA  GLY A   1       1.450   0.000   0.000  0.0000 1.7000\n"
    "ATOM      3  C   GLY A   1       2.000   1.400   0.000  0.0000 1.7000\n"
    "ATOM      4  O   GLY A   1       1.300   2.400   0.300  0.0000 1.5200\n";

class Batch : public testing_support::FolderTest {
 protected:
  void SetUp() override {
    FolderTest::SetUp();
    fs::create_directories(folder_ / "in");
  }

  // A small mixed set: two good meshes, a structure, an open mesh (refused, 2), garbage (unreadable, 1).
  std::vector<fs::path> mixed_set() {
    const fs::path in = folder_ / "in";
    write_ply(in / "ico.ply", make_icosphere(2));
    write_ply(in / "dumbbell.ply", make_dumbbell(3, 0.4, 16, 12));
    Mesh open = make_icosphere(1);
    open.triangles.pop_back();
    write_ply(in / "open.ply", open);
    write_text(in / "garbage.obj", "this, is \"not\" a mesh\n");
    write_text(in / "tiny.pqr", kTinyPqr);
    return expand_batch_inputs({in.string()});
  }

  BatchOptions fast_options(int jobs = 2) {
    BatchOptions options;
    options.jobs = jobs;
    options.job.surface.grid = 0.6;
    return options;
  }
};

TEST_F(Batch, ExpandsFoldersGlobsAndListsInADeterministicOrder) {
  const fs::path in = folder_ / "in";
  for (const char* name : {"b.ply", "a.OBJ", "c.stl", "d.pdb.gz", "e.cif", "notes.md", ".hidden.ply", "z.off"})
    write_text(in / name, "x");
  write_text(in / "sub" / "deep.ply", "x");
  const auto folder = expand_batch_inputs({in.string()});
  std::vector<std::string> names;
  for (const auto& path : folder) names.push_back(path.filename().string());
  EXPECT_EQ(names, (std::vector<std::string>{"a.OBJ", "b.ply", "c.stl", "d.pdb.gz", "e.cif", "z.off"}));

  // A quoted glob: sorted matches, taken whatever their extension (like the shell's expansion).
  const auto globbed = expand_batch_inputs({(in / "[bn]*").string()});
  ASSERT_EQ(globbed.size(), 2u);
  EXPECT_EQ(globbed[0].filename(), "b.ply");
  EXPECT_EQ(globbed[1].filename(), "notes.md");

  // Lists: comments, blank lines, paths relative to the list, nested lists; duplicates once (first wins);
  // a missing file is kept (its run fails with the reader's message).
  write_text(folder_ / "lists" / "inner.txt", "../in/c.stl\n");
  write_text(folder_ / "lists" / "main.list",
             "# inputs\n\n  ../in/z.off  \ninner.txt\n../in/b.ply\n../in/missing.ply\n");
  const auto listed = expand_batch_inputs(
      {"@" + (folder_ / "lists" / "main.list").string(), (in / "b.ply").string(), (in / "z.off").string()});
  names.clear();
  for (const auto& path : listed) names.push_back(path.filename().string());
  EXPECT_EQ(names, (std::vector<std::string>{"z.off", "c.stl", "b.ply", "missing.ply"}));

  fs::create_directories(folder_ / "empty");
  EXPECT_THROW(expand_batch_inputs({(folder_ / "empty").string()}), InputError);
  EXPECT_THROW(expand_batch_inputs({"@" + (folder_ / "no-such-list").string()}), InputError);
  write_text(folder_ / "loop.txt", "loop.txt\n");
  EXPECT_THROW(expand_batch_inputs({(folder_ / "loop.txt").string()}), InputError);
}

TEST_F(Batch, OutputNamesAreUniqueAndDocumented) {
  const auto inputs = name_batch_inputs({"x/1crn.cif.gz", "x/1abc.pdb", "y/1ABC.cif", "x/ico.ply", "y/ico.ply",
                                         "z/ico.ply", "x/summary.csv.obj", "x/2xyz.pdb"});
  std::vector<std::string> names;
  for (const auto& input : inputs) names.push_back(input.name);
  EXPECT_EQ(names, (std::vector<std::string>{"1crn", "1abc.pdb", "1ABC.cif", "ico.ply", "ico.ply~2", "ico.ply~3",
                                             "summary.csv.obj", "2xyz"}));
  const std::vector<Weights> one = {Weights::kUniform};
  const std::vector<Weights> two = {Weights::kUniform, Weights::kMeanValue};
  EXPECT_EQ(batch_run_folder("r", inputs[0], one, 0), fs::path("r/1crn"));
  EXPECT_EQ(batch_run_folder("r", inputs[0], two, 1), fs::path("r/1crn/mean-value"));
}

TEST_F(Batch, CsvIsQuotedAsRfc4180) {
  Json row = Json::object();
  for (const auto& column : summary_columns()) row[column] = nullptr;
  row["input"] = "a, \"b\".ply";
  row["message"] = "line one\nline two, with comma";
  row["vertices"] = 12;
  row["coverage"] = 1.0000000000000002;
  row["certified"] = true;
  row["output"] = " padded";
  const auto text = summary_csv({row});
  const auto rows = parse_csv(text);
  ASSERT_EQ(rows.size(), 2u);
  ASSERT_EQ(rows[0].size(), summary_columns().size());
  ASSERT_EQ(rows[1].size(), summary_columns().size());
  std::map<std::string, std::string> fields;
  for (std::size_t k = 0; k < rows[0].size(); ++k) fields[rows[0][k]] = rows[1][k];
  EXPECT_EQ(fields["input"], "a, \"b\".ply");
  EXPECT_EQ(fields["message"], "line one\nline two, with comma");
  EXPECT_EQ(fields["vertices"], "12");
  EXPECT_EQ(fields["coverage"], "1.0000000000000002");
  EXPECT_EQ(fields["certified"], "true");
  EXPECT_EQ(fields["output"], " padded");
  EXPECT_EQ(fields["atoms"], "");
  EXPECT_NE(text.find("\"a, \"\"b\"\".ply\""), std::string::npos) << text;
  EXPECT_EQ(Json::parse(summary_jsonl({row})), row);
}

TEST_F(Batch, ABrokenInputNeverStopsTheOthers) {
  const auto inputs = name_batch_inputs(mixed_set());
  const fs::path root = folder_ / "out";
  const auto result = run_batch(root, inputs, fast_options());
  ASSERT_EQ(result.rows.size(), 5u);
  std::map<std::string, Json> by_name;
  for (const auto& row : result.rows) by_name[row["output"].get<std::string>()] = row;
  for (const char* name : {"ico", "dumbbell", "tiny"}) {
    EXPECT_EQ(by_name[name]["status"], "ok") << by_name[name].dump();
    for (const char* file : {"surface.ply", "sphere.ply", "report.json"}) EXPECT_TRUE(fs::exists(root / name / file));
    EXPECT_FALSE(fs::exists(root / name / kRunErrorFile));
    EXPECT_GT(by_name[name]["vertices"].get<int>(), 0);
    EXPECT_EQ(by_name[name]["folded"], 0);
  }
  EXPECT_GT(by_name["tiny"]["atoms"].get<int>(), 0);
  EXPECT_TRUE(by_name["ico"]["atoms"].is_null());
  EXPECT_EQ(by_name["ico"]["genus_before_repair"], 0);
  EXPECT_EQ(by_name["open"]["status"], "error");
  EXPECT_EQ(by_name["open"]["exit_code"], 2);
  EXPECT_EQ(by_name["garbage"]["status"], "error");
  EXPECT_EQ(by_name["garbage"]["exit_code"], 1);
  for (const char* name : {"open", "garbage"}) {
    EXPECT_FALSE(by_name[name]["message"].get<std::string>().empty());
    EXPECT_TRUE(fs::exists(root / name / kRunErrorFile));
    EXPECT_FALSE(fs::exists(root / name / "surface.ply"));
    EXPECT_FALSE(fs::exists(root / name / kRunReportFile));
  }
  EXPECT_EQ(result.exit_code, 1);  // unreadable outranks refused
  EXPECT_EQ(result.progress.finished, 5u);
  // Rows in input order (the folder's sorted order), not in completion order.
  std::vector<std::string> order;
  for (const auto& row : result.rows) order.push_back(row["output"]);
  EXPECT_EQ(order, (std::vector<std::string>{"dumbbell", "garbage", "ico", "open", "tiny"}));
  // The files on disk are the rows returned, and every row has every column.
  EXPECT_EQ(slurp(root / "summary.csv"), summary_csv(result.rows));
  EXPECT_EQ(slurp(root / "summary.jsonl"), summary_jsonl(result.rows));
  for (const auto& row : parse_csv(slurp(root / "summary.csv"))) EXPECT_EQ(row.size(), summary_columns().size());
}

TEST_F(Batch, ExitCodeRule) {
  auto rows = [](std::vector<std::pair<std::string, int>> statuses) {
    std::vector<Json> out;
    for (const auto& [status, code] : statuses) out.push_back({{"status", status}, {"exit_code", code}});
    return out;
  };
  EXPECT_EQ(batch_exit_code(rows({{"ok", 0}, {"ok", 0}})), 0);
  EXPECT_EQ(batch_exit_code(rows({{"ok", 0}, {"not-certified", 3}})), 3);
  EXPECT_EQ(batch_exit_code(rows({{"not-certified", 3}, {"error", 2}})), 2);
  EXPECT_EQ(batch_exit_code(rows({{"error", 2}, {"error", 1}, {"not-certified", 3}})), 1);
  EXPECT_EQ(batch_exit_code(rows({{"error", 1}, {"error", 4}})), 4);
  EXPECT_EQ(batch_exit_code(rows({{"ok", 0}, {"pending", 0}})), 4);
}

TEST_F(Batch, SeveralWeightingsGetOneSubfolderEachAndOneRowEach) {
  write_ply(folder_ / "in" / "ico.ply", make_icosphere(2));
  write_text(folder_ / "in" / "bad.off", "OFF\n3 1 0\n0 0 0\n");
  const auto inputs = name_batch_inputs(expand_batch_inputs({(folder_ / "in").string()}));
  BatchOptions options = fast_options();
  options.weights = {Weights::kMeanValue, Weights::kUniform};
  const auto result = run_batch(folder_ / "out", inputs, options);
  ASSERT_EQ(result.rows.size(), 4u);
  EXPECT_EQ(result.rows[0]["output"], "bad/mean-value");
  EXPECT_EQ(result.rows[1]["output"], "bad/uniform");
  EXPECT_EQ(result.rows[2]["output"], "ico/mean-value");
  EXPECT_EQ(result.rows[3]["output"], "ico/uniform");
  EXPECT_EQ(result.rows[0]["status"], "error");
  EXPECT_EQ(result.rows[1]["status"], "error");
  EXPECT_EQ(result.rows[2]["status"], "ok");
  EXPECT_EQ(result.rows[3]["status"], "ok");
  EXPECT_EQ(result.rows[2]["weights"], "mean-value");
  EXPECT_EQ(Json::parse(slurp(folder_ / "out" / "ico" / "mean-value" / "report.json"))["options"]["weights"],
            "mean-value");
  EXPECT_EQ(Json::parse(slurp(folder_ / "out" / "ico" / "uniform" / "report.json"))["options"]["weights"], "uniform");
}

TEST_F(Batch, ParallelOutputsAreIdenticalToSerialOnes) {
  const auto inputs = name_batch_inputs(mixed_set());
  auto in_process = fast_options(1);
  in_process.isolate = false;  // the reference: one input after the other, in this process
  const auto serial = run_batch(folder_ / "serial", inputs, in_process);
  const auto parallel = run_batch(folder_ / "parallel", inputs, fast_options(2));
  EXPECT_EQ(csv_without_timings(summary_csv(serial.rows)), csv_without_timings(summary_csv(parallel.rows)));
  for (const auto& input : inputs)
    for (const char* file : {"surface.ply", "sphere.ply", "error.json"})
      EXPECT_EQ(slurp(folder_ / "serial" / input.name / file), slurp(folder_ / "parallel" / input.name / file))
          << input.name << "/" << file;
}

TEST_F(Batch, ResumesToTheSameSummaryAndSkipsWhatIsComplete) {
  const auto inputs = name_batch_inputs(mixed_set());
  const fs::path root = folder_ / "out";
  const auto first = run_batch(root, inputs, fast_options());
  const std::string csv = slurp(root / "summary.csv"), jsonl = slurp(root / "summary.jsonl");

  // Nothing to do: nothing runs, and the summary is byte for byte the same.
  const auto again = run_batch(root, inputs, fast_options());
  EXPECT_EQ(again.progress.finished, 0u);
  EXPECT_EQ(again.progress.already_done, inputs.size());
  EXPECT_EQ(slurp(root / "summary.csv"), csv);
  EXPECT_EQ(slurp(root / "summary.jsonl"), jsonl);

  // As if killed while writing ico's outputs: no report.json, a stale PLY and leftover temporary files;
  // and the summary files lost too.
  const std::string dumbbell_report = slurp(root / "dumbbell" / "report.json");
  fs::remove(root / "ico" / "report.json");
  write_text(root / "ico" / "sphere.ply.tmp-999999", "partial");
  write_text(root / "summary.csv.tmp-999999", "partial");
  fs::remove(root / "summary.csv");
  fs::remove(root / "summary.jsonl");
  const auto resumed = run_batch(root, inputs, fast_options());
  EXPECT_EQ(resumed.progress.finished, 1u);  // ico only
  EXPECT_EQ(resumed.progress.already_done, inputs.size() - 1);
  EXPECT_FALSE(fs::exists(root / "ico" / "sphere.ply.tmp-999999"));
  EXPECT_FALSE(fs::exists(root / "summary.csv.tmp-999999"));
  EXPECT_EQ(slurp(root / "dumbbell" / "report.json"), dumbbell_report);  // not redone
  EXPECT_EQ(csv_without_timings(slurp(root / "summary.csv")), csv_without_timings(csv));
  EXPECT_EQ(jsonl_without_timings(slurp(root / "summary.jsonl")), jsonl_without_timings(jsonl));
  EXPECT_EQ(resumed.exit_code, first.exit_code);
}

TEST_F(Batch, ErrorsAreRetriedOnlyWhenAskedAndForceRedoesEverything) {
  const auto inputs = name_batch_inputs(mixed_set());
  const fs::path root = folder_ / "out";
  run_batch(root, inputs, fast_options());
  // Fix the garbage file: without --retry-errors its error stands.
  std::string obj;
  const Mesh icosahedron = make_icosphere(0);
  for (const auto& p : icosahedron.positions) obj += fmt::format("v {} {} {}\n", p[0], p[1], p[2]);
  for (const auto& t : icosahedron.triangles) obj += fmt::format("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
  write_text(folder_ / "in" / "garbage.obj", obj);
  auto options = fast_options();
  EXPECT_EQ(run_batch(root, inputs, options).progress.finished, 0u);
  options.retry_errors = true;
  const auto retried = run_batch(root, inputs, options);
  EXPECT_EQ(retried.progress.finished, 2u);  // open (still refused) and garbage (now fine)
  EXPECT_EQ(retried.rows[1]["output"], "garbage");
  EXPECT_EQ(retried.rows[1]["status"], "ok");
  EXPECT_FALSE(fs::exists(root / "garbage" / kRunErrorFile));
  EXPECT_EQ(retried.exit_code, 2);
  options.retry_errors = false;
  options.force = true;
  write_text(root / "ico" / "unrelated.txt", "kept");
  const auto forced = run_batch(root, inputs, options);
  EXPECT_EQ(forced.progress.finished, inputs.size());
  EXPECT_EQ(forced.progress.already_done, 0u);
  EXPECT_TRUE(fs::exists(root / "ico" / "unrelated.txt"));
  EXPECT_TRUE(fs::exists(root / "ico" / "report.json"));
}

TEST_F(Batch, RefusesAFolderMadeWithOtherOptionsUnlessForced) {
  write_ply(folder_ / "in" / "ico.ply", make_icosphere(1));
  const auto inputs = name_batch_inputs(expand_batch_inputs({(folder_ / "in").string()}));
  const fs::path root = folder_ / "out";
  run_batch(root, inputs, fast_options());
  auto other = fast_options();
  other.job.ascii = true;
  other.job.surface.grid = 0.5;
  try {
    run_batch(root, inputs, other);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("ascii true (was false)"), std::string::npos) << message;
    EXPECT_NE(message.find("surface.grid 0.5 (was 0.6)"), std::string::npos) << message;
    EXPECT_NE(message.find("--force"), std::string::npos) << message;
  }
  other.force = true;
  EXPECT_EQ(run_batch(root, inputs, other).progress.finished, 1u);
  EXPECT_EQ(slurp(root / "ico" / "sphere.ply").rfind("ply\nformat ascii", 0), 0u);
  other.force = false;
  EXPECT_EQ(run_batch(root, inputs, other).progress.finished, 0u);  // the new options are the folder's now
}

TEST_F(Batch, OneBatchPerFolderAtATime) {
  const BatchLock lock(folder_ / "out");
  EXPECT_THROW(BatchLock(folder_ / "out"), InputError);
  write_ply(folder_ / "in" / "ico.ply", make_icosphere(1));
  EXPECT_THROW(run_batch(folder_ / "out", name_batch_inputs({folder_ / "in" / "ico.ply"}), fast_options()), InputError);
}

// The lock is the batch's: a child forked to map an input (which outlives a killed batch by the time
// its PDEATHSIG takes) must not keep it, or a batch resumed at once is refused.
TEST_F(Batch, TheLockEndsWithTheBatchNotWithAChildItForked) {
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  std::optional<BatchLock> lock(std::in_place, folder_ / "out");
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    lock->forget_in_child();
    const char byte = 1;
    if (::write(ready[1], &byte, 1) != 1) ::_exit(2);
    ::pause();  // alive, as a child still dying is, until the test kills it
    ::_exit(0);
  }
  char byte = 0;
  ASSERT_EQ(::read(ready[0], &byte, 1), 1);
  lock.reset();  // the batch ends; its child lives on
  EXPECT_NO_THROW(BatchLock(folder_ / "out"));
  ::kill(child, SIGKILL);
  ::waitpid(child, nullptr, 0);
  ::close(ready[0]), ::close(ready[1]);
}

TEST_F(Batch, StopRequestFinishesTheRunningInputAndLeavesTheRestPending) {
  const auto inputs = name_batch_inputs(mixed_set());
  const fs::path root = folder_ / "out";
  BatchCallbacks callbacks;
  std::size_t finished = 0;
  callbacks.on_finished = [&](const BatchInputOutcome&, const BatchProgress&) { ++finished; };
  callbacks.stop = [&] { return finished >= 1 ? BatchStop::kFinishRunning : BatchStop::kContinue; };
  const auto stopped = run_batch(root, inputs, fast_options(1), callbacks);
  EXPECT_TRUE(stopped.stopped);
  EXPECT_LT(stopped.progress.finished, inputs.size());
  std::size_t pending = 0;
  for (const auto& row : stopped.rows) pending += row["status"] == "pending";
  EXPECT_EQ(pending, inputs.size() - stopped.progress.finished);
  const auto resumed = run_batch(root, inputs, fast_options());
  EXPECT_FALSE(resumed.stopped);
  EXPECT_EQ(resumed.progress.finished, pending);
  for (const auto& row : resumed.rows) EXPECT_NE(row["status"], "pending");
}

// The children of this process (Linux: /proc/self/task/*/children).
std::vector<pid_t> child_processes() {
  std::vector<pid_t> children;
  for (const auto& task : fs::directory_iterator("/proc/self/task")) {
    std::istringstream list(slurp(task.path() / "children"));
    for (pid_t pid; list >> pid;) children.push_back(pid);
  }
  return children;
}

TEST_F(Batch, AKilledOrCrashedChildCostsItsInputOnly) {
  for (int k = 0; k < 3; ++k)
    write_ply(folder_ / "in" / fmt::format("m{}.ply", k),
              random_edge_flips(perturb_vertices(make_icosphere(5), 0.2, 10 + k), 0.1, 20 + k));
  const auto inputs = name_batch_inputs(expand_batch_inputs({(folder_ / "in").string()}));
  std::thread killer([&] {
    for (int k = 0; k < 20000; ++k) {  // at most 20 s
      const auto children = child_processes();
      if (!children.empty()) {
        kill(children.front(), SIGKILL);  // as the out-of-memory killer would
        return;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  });
  const auto result = run_batch(folder_ / "out", inputs, fast_options(1));
  killer.join();
  ASSERT_EQ(result.rows.size(), 3u);
  EXPECT_EQ(result.rows[0]["status"], "error") << result.rows[0].dump();
  EXPECT_EQ(result.rows[0]["exit_code"], 4);
  EXPECT_NE(result.rows[0]["message"].get<std::string>().find("signal 9"), std::string::npos) << result.rows[0].dump();
  EXPECT_FALSE(fs::exists(folder_ / "out" / "m0" / "report.json"));
  EXPECT_EQ(result.rows[1]["status"], "ok");
  EXPECT_EQ(result.rows[2]["status"], "ok");
  EXPECT_EQ(result.exit_code, 4);
}

// --- The command line, killed in the middle of a batch --------------------------------------------

pid_t spawn_cli(const std::vector<std::string>& arguments, const fs::path& log) {
  std::vector<std::string> argv_text = {SPHEREMAP_CLI_PATH};
  argv_text.insert(argv_text.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (auto& a : argv_text) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = -1;
  const int error = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  return error == 0 ? pid : -1;
}

int wait_exit_code(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

class BatchCli : public Batch {
 protected:
  // Eight meshes that take a moment each, so that a kill lands in the middle of the batch.
  std::vector<std::string> slow_set() {
    for (int k = 0; k < 8; ++k)
      write_ply(folder_ / "in" / fmt::format("m{}.ply", k),
                random_edge_flips(perturb_vertices(make_icosphere(4), 0.2, 10 + k), 0.1, 20 + k));
    return {"batch", (folder_ / "in").string(), "--jobs", "1", "-q"};
  }

  // Waits (at most 60 s) until some input of `root` is complete.
  static bool wait_for_first_report(const fs::path& root, pid_t pid) {
    for (int k = 0; k < 60000; ++k) {
      for (int m = 0; m < 8; ++m)
        if (fs::exists(root / fmt::format("m{}", m) / "report.json")) return true;
      int status = 0;
      if (waitpid(pid, &status, WNOHANG) == pid) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return false;
  }
};

TEST_F(BatchCli, KilledBatchResumesToTheSameSummary) {
  auto arguments = slow_set();
  const fs::path reference = folder_ / "reference", killed = folder_ / "killed";
  auto with_output = [&](const fs::path& root) {
    auto a = arguments;
    a.insert(a.end(), {"-o", root.string()});
    return a;
  };
  ASSERT_EQ(wait_exit_code(spawn_cli(with_output(reference), folder_ / "log.txt")), 0) << slurp(folder_ / "log.txt");

  const pid_t pid = spawn_cli(with_output(killed), folder_ / "log.txt");
  ASSERT_GT(pid, 0);
  ASSERT_TRUE(wait_for_first_report(killed, pid)) << slurp(folder_ / "log.txt");
  kill(pid, SIGKILL);
  EXPECT_EQ(wait_exit_code(pid), 128 + SIGKILL);
  std::size_t complete = 0;
  for (int m = 0; m < 8; ++m) complete += fs::exists(killed / fmt::format("m{}", m) / "report.json");
  EXPECT_LT(complete, 8u) << "the kill came too late to test anything";

  ASSERT_EQ(wait_exit_code(spawn_cli(with_output(killed), folder_ / "log.txt")), 0) << slurp(folder_ / "log.txt");
  EXPECT_EQ(csv_without_timings(slurp(killed / "summary.csv")), csv_without_timings(slurp(reference / "summary.csv")));
  EXPECT_EQ(jsonl_without_timings(slurp(killed / "summary.jsonl")),
            jsonl_without_timings(slurp(reference / "summary.jsonl")));
  for (int m = 0; m < 8; ++m)
    EXPECT_EQ(slurp(killed / fmt::format("m{}", m) / "sphere.ply"),
              slurp(reference / fmt::format("m{}", m) / "sphere.ply"));
  for (const auto& entry : fs::recursive_directory_iterator(killed))
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();

  // Re-running a complete batch changes nothing, byte for byte.
  const std::string csv = slurp(killed / "summary.csv");
  ASSERT_EQ(wait_exit_code(spawn_cli(with_output(killed), folder_ / "log.txt")), 0);
  EXPECT_EQ(slurp(killed / "summary.csv"), csv);
}

TEST_F(BatchCli, TerminatedBatchWritesWhatIsCompleteAndExits143) {
  auto arguments = slow_set();
  const fs::path root = folder_ / "out";
  arguments.insert(arguments.end(), {"-o", root.string()});
  const pid_t pid = spawn_cli(arguments, folder_ / "log.txt");
  ASSERT_GT(pid, 0);
  ASSERT_TRUE(wait_for_first_report(root, pid)) << slurp(folder_ / "log.txt");
  kill(pid, SIGTERM);
  EXPECT_EQ(wait_exit_code(pid), 128 + SIGTERM) << slurp(folder_ / "log.txt");
  const auto rows = parse_csv(slurp(root / "summary.csv"));
  ASSERT_EQ(rows.size(), 9u);
  std::size_t ok = 0;
  for (std::size_t r = 1; r < rows.size(); ++r) ok += rows[r][3] == "ok";
  std::size_t complete = 0;
  for (int m = 0; m < 8; ++m) complete += fs::exists(root / fmt::format("m{}", m) / "report.json");
  EXPECT_EQ(ok, complete);
  EXPECT_GE(ok, 1u);
  EXPECT_EQ(wait_exit_code(spawn_cli(arguments, folder_ / "log.txt")), 0) << slurp(folder_ / "log.txt");
  EXPECT_EQ(parse_csv(slurp(root / "summary.csv")).size(), 9u);
  for (const auto& row : parse_csv(slurp(root / "summary.csv"))) EXPECT_NE(row[3], "pending");
}

TEST_F(BatchCli, ExitCodesAndOneLinePerInputWithoutATerminal) {
  mixed_set();
  const fs::path root = folder_ / "out";
  const pid_t pid = spawn_cli({"batch", (folder_ / "in").string(), (folder_ / "in" / "*.ply").string(), "-o",
                               root.string(), "--jobs", "2", "--grid", "0.6"},
                              folder_ / "log.txt");
  EXPECT_EQ(wait_exit_code(pid), 1);
  const std::string log = slurp(folder_ / "log.txt");
  for (const char* name : {"ico", "dumbbell", "tiny", "open", "garbage"})
    EXPECT_NE(log.find(fmt::format("-> {}: ", name)), std::string::npos) << name << "\n" << log;
  EXPECT_NE(log.find("2 error(s)"), std::string::npos) << log;
  EXPECT_EQ(parse_csv(slurp(root / "summary.csv")).size(), 6u);  // the glob's files were already in: once each
  // Only good inputs: 0.
  EXPECT_EQ(
      wait_exit_code(spawn_cli({"batch", (folder_ / "in" / "ico.ply").string(), "-o", (folder_ / "good").string()},
                               folder_ / "log.txt")),
      0);
  // A bad command line: 1, nothing written.
  EXPECT_EQ(wait_exit_code(spawn_cli(
                {"batch", (folder_ / "in").string(), "-o", (folder_ / "bad").string(), "--weights", "uniform,uniform"},
                folder_ / "log.txt")),
            1);
  EXPECT_FALSE(fs::exists(folder_ / "bad" / "summary.csv"));
}

// --- Batches under faults: kills at random moments, a full disk -------------------------------------

// Twelve inputs, three of them bad (open, a NaN vertex, empty), small enough that a batch takes a moment.
class BatchFaults : public BatchCli {
 protected:
  std::vector<std::string> faulty_set() {
    const fs::path in = folder_ / "in";
    for (int k = 0; k < 9; ++k)
      write_ply(in / fmt::format("good{}.ply", k), perturb_vertices(make_icosphere(2), 0.1, 40 + k));
    Mesh open = make_icosphere(1);
    open.triangles.pop_back();
    write_ply(in / "bad-open.ply", open);
    write_text(in / "bad-nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n");
    write_text(in / "bad-empty.stl", "");
    return {"batch", in.string(), "--jobs", "2", "-q"};
  }

  static std::vector<std::string> with_output(std::vector<std::string> arguments, const fs::path& root,
                                              std::initializer_list<const char*> more = {}) {
    arguments.insert(arguments.end(), {"-o", root.string()});
    arguments.insert(arguments.end(), more.begin(), more.end());
    return arguments;
  }

  // The batch's running children (Linux: /proc/PID/task/PID/children), empty if none or unknown.
  static std::vector<pid_t> children_of(pid_t pid) {
    std::ifstream in(fmt::format("/proc/{}/task/{}/children", pid, pid));
    std::vector<pid_t> children;
    for (pid_t child; in >> child;) children.push_back(child);
    return children;
  }

  // Every complete run folder of `root` (report.json present) holds exactly the reference's PLY files.
  void expect_complete_runs_match(const fs::path& root, const fs::path& reference) {
    for (const auto& entry : fs::directory_iterator(root)) {
      if (!entry.is_directory() || !fs::exists(entry.path() / "report.json")) continue;
      const auto name = entry.path().filename();
      for (const char* file : {"surface.ply", "sphere.ply"})
        EXPECT_EQ(slurp(entry.path() / file), slurp(reference / name / file)) << name << "/" << file;
    }
  }

  static void expect_no_temporaries(const fs::path& root) {
    for (const auto& entry : fs::recursive_directory_iterator(root))
      EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
  }
};

TEST_F(BatchFaults, KilledAtRandomMomentsResumesToTheUninterruptedSummary) {
  const auto arguments = faulty_set();
  const fs::path reference = folder_ / "reference", killed = folder_ / "killed";
  ASSERT_EQ(wait_exit_code(spawn_cli(with_output(arguments, reference), folder_ / "log.txt")), 1)
      << slurp(folder_ / "log.txt");
  const auto rows = parse_csv(slurp(reference / "summary.csv"));
  ASSERT_EQ(rows.size(), 13u);
  std::size_t errors = 0;
  for (std::size_t r = 1; r < rows.size(); ++r) {
    const bool bad = rows[r][0].find("bad-") != std::string::npos;
    EXPECT_EQ(rows[r][3] == "error", bad) << rows[r][0] << ": " << rows[r][3];
    errors += rows[r][3] == "error";
  }
  EXPECT_EQ(errors, 3u);

  // Kills at seeded random moments: of the batch itself, or of one of the children it forked.
  std::mt19937 random(2026);
  int kills = 0, finished_alone = 0;
  for (int round = 0; round < 8; ++round) {
    const pid_t pid = spawn_cli(with_output(arguments, killed, {"--retry-errors"}), folder_ / "log.txt");
    ASSERT_GT(pid, 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(std::uniform_int_distribution<int>(5, 150)(random)));
    const auto children = children_of(pid);
    if (round % 2 == 1 && !children.empty()) {
      ::kill(children.front(), SIGKILL);  // as the out-of-memory killer would
    } else {
      ::kill(pid, SIGKILL);
    }
    ++kills;
    const int code = wait_exit_code(pid);
    if (code == 0 || code == 1) ++finished_alone;
  }
  ASSERT_EQ(wait_exit_code(spawn_cli(with_output(arguments, killed, {"--retry-errors"}), folder_ / "log.txt")), 1)
      << slurp(folder_ / "log.txt");
  EXPECT_EQ(csv_without_timings(slurp(killed / "summary.csv")), csv_without_timings(slurp(reference / "summary.csv")));
  EXPECT_EQ(jsonl_without_timings(slurp(killed / "summary.jsonl")),
            jsonl_without_timings(slurp(reference / "summary.jsonl")));
  expect_complete_runs_match(killed, reference);
  expect_no_temporaries(killed);
  RecordProperty("kills", kills);
  RecordProperty("finished_before_the_kill", finished_alone);
}

// A full disk, simulated by RLIMIT_FSIZE (writes beyond it fail with EFBIG; SIGXFSZ ignored): the batch
// fails the inputs it cannot write, trusts none of their half-written files, and a later run with room
// (--retry-errors) gives the uninterrupted summary.
TEST_F(BatchFaults, AFullDiskFailsRowsAndARunWithRoomRepairsThem) {
  const auto arguments = faulty_set();
  const fs::path reference = folder_ / "reference", full = folder_ / "full";
  ASSERT_EQ(wait_exit_code(spawn_cli(with_output(arguments, reference), folder_ / "log.txt")), 1);
  std::vector<std::string> argv_text = {SPHEREMAP_CLI_PATH};
  for (const auto& a : with_output(arguments, full)) argv_text.push_back(a);
  std::vector<char*> argv;
  for (auto& a : argv_text) argv.push_back(a.data());
  argv.push_back(nullptr);
  const std::string log = (folder_ / "full-log.txt").string();
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(fd, 1);
    ::dup2(fd, 2);
    ::signal(SIGXFSZ, SIG_IGN);
    const rlimit limit{6000, 6000};  // bytes per file: every PLY of these meshes is larger
    ::setrlimit(RLIMIT_FSIZE, &limit);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  ASSERT_GT(pid, 0);
  const int code = wait_exit_code(pid);
  EXPECT_TRUE(code == 1 || code == 4) << code << "\n" << slurp(log);
  EXPECT_EQ(slurp(log).find("internal error"), std::string::npos) << slurp(log);
  // Every good input failed its row for want of room, saying so (on the terminal: the summary may not fit).
  for (int k = 0; k < 9; ++k) {
    const std::string message = slurp(full / fmt::format("good{}", k) / "error.json");
    EXPECT_NE(message.find("cannot write the file (File too large)"), std::string::npos) << k << ": " << message;
  }
  expect_complete_runs_match(full, reference);
  expect_no_temporaries(full);
  ASSERT_EQ(wait_exit_code(spawn_cli(with_output(arguments, full, {"--retry-errors"}), folder_ / "log.txt")), 1)
      << slurp(folder_ / "log.txt");
  EXPECT_EQ(csv_without_timings(slurp(full / "summary.csv")), csv_without_timings(slurp(reference / "summary.csv")));
  expect_complete_runs_match(full, reference);
}

// --- Real structures -------------------------------------------------------------------------------

class DataBatch : public testing_support::FolderTest {};

TEST_F(DataBatch, PaperStructuresAtThePaperPresetInParallel) {
  const fs::path data = fs::path(SPHEREMAP_SHARED_DATA_DIR) / "pdb" / "paper77";
  std::vector<fs::path> files;
  for (const char* name : {"1etl.pdb", "1etm.pdb", "2dcg.cif"})
    if (fs::exists(data / name)) files.push_back(data / name);
  if (files.size() < 3) GTEST_SKIP() << "needs " << data << "/{1etl.pdb,1etm.pdb,2dcg.cif} (../shared/data)";
  const fs::path root = folder_;
  BatchOptions options;
  options.job.surface.probe = 1.8;  // --preset paper
  options.job.surface.grid = 2.5;
  options.weights = {Weights::kUniform, Weights::kMeanValue};
  options.jobs = 2;
  const auto inputs = name_batch_inputs(files);
  const auto parallel = run_batch(root / "parallel", inputs, options);
  options.jobs = 1;
  const auto serial = run_batch(root / "serial", inputs, options);
  ASSERT_EQ(parallel.rows.size(), 6u);
  for (const auto& row : parallel.rows) {
    EXPECT_TRUE(row["status"] == "ok" || row["status"] == "not-certified") << row.dump();
    EXPECT_GT(row["atoms"].get<int>(), 20) << row.dump();
    EXPECT_GT(row["triangles"].get<int>(), 100) << row.dump();
    EXPECT_FALSE(row["repair_method"].is_null()) << row.dump();
    // Rounds are counted only for a per-handle repair.
    EXPECT_EQ(row["repair_rounds"].get<int>() > 0, row["repair_method"] == "per-handle") << row.dump();
  }
  EXPECT_EQ(csv_without_timings(summary_csv(parallel.rows)), csv_without_timings(summary_csv(serial.rows)));
  for (const auto& input : inputs)
    for (const char* weights : {"uniform", "mean-value"})
      EXPECT_EQ(slurp(root / "parallel" / input.name / weights / "sphere.ply"),
                slurp(root / "serial" / input.name / weights / "sphere.ply"));
}

}  // namespace
}  // namespace spheremap
