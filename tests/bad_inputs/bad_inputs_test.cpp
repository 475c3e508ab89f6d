// The bad-input table (tests/bad_inputs/cases.tsv): the command line run on every bad input and option,
// each in a fresh folder holding a copy of tests/bad_inputs/files/ and the generated files below. Every case
// checks its documented exit code, a message that names the file (or option) and the problem, that it
// exits (no signal: no crash) within 30 s (no hang), that nothing is left behind (the folder's tree is
// unchanged, for failing cases), and that everything it printed or wrote is valid UTF-8.
// How to add a case: CONTRIBUTING.md ("Adding a bad-input case").
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "../test_support.hpp"
#include "spheremap/text.hpp"

namespace spheremap {
namespace {

namespace fs = std::filesystem;
using testing_support::slurp;
using testing_support::write_text;

constexpr auto kTimeLimit = std::chrono::seconds(30);
const fs::path kTableFolder = fs::path(SPHEREMAP_SOURCE_DIR) / "tests" / "bad_inputs";
// {latin1} in a case's arguments: a file name that is not valid UTF-8 (ISO 8859-1 'é').
const std::string kLatin1Name = "caf\xe9";
// The output root of the cases that run `batch`.
constexpr const char* kBatchRoot = "runs";

struct BadInputCase {
  std::string name;       // [A-Za-z0-9_]: the test's name
  int exit_code = 0;      // expected
  std::string names;      // the message names this (the file, or the option)
  std::string problem;    // and says this
  std::string arguments;  // of spheremap, split at spaces; run in the case's folder
};

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(text);
  while (std::getline(in, part, separator)) parts.push_back(part);
  return parts;
}

// cases.tsv: name, exit code, what the message names, the problem, the arguments; '#' starts a comment line.
std::vector<BadInputCase> read_cases() {
  std::vector<BadInputCase> cases;
  std::ifstream in(kTableFolder / "cases.tsv");
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    const auto fields = split(line, '\t');
    BadInputCase c;
    c.name = fields.at(0);
    if (fields.size() != 5) {
      c.exit_code = -1;  // reported by the test
      c.arguments = line;
    } else {
      c.exit_code = std::stoi(fields[1]);
      c.names = fields[2];
      c.problem = fields[3];
      c.arguments = fields[4];
    }
    cases.push_back(c);
  }
  return cases;
}

std::string gzip(const std::string& bytes) {
  z_stream z{};
  if (deflateInit2(&z, Z_BEST_COMPRESSION, Z_DEFLATED, 16 + MAX_WBITS, 8, Z_DEFAULT_STRATEGY) != Z_OK) return {};
  std::string out(compressBound(static_cast<uLong>(bytes.size())) + 64, '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
  z.avail_in = static_cast<uInt>(bytes.size());
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = static_cast<uInt>(out.size());
  deflate(&z, Z_FINISH);
  out.resize(z.total_out);
  deflateEnd(&z);
  return out;
}

// A gzip bomb: `megabytes` MiB of zero bytes in a gzip stream of about a thousandth of that.
std::string gzip_of_zeros(std::size_t megabytes) {
  z_stream z{};
  if (deflateInit2(&z, 1, Z_DEFLATED, 16 + MAX_WBITS, 8, Z_DEFAULT_STRATEGY) != Z_OK) return {};
  const std::string zeros(std::size_t{1} << 20, '\0');
  std::string out, buffer(std::size_t{1} << 16, '\0');
  for (std::size_t m = 0; m < megabytes; ++m) {
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(zeros.data()));
    z.avail_in = static_cast<uInt>(zeros.size());
    const int flush = m + 1 == megabytes ? Z_FINISH : Z_NO_FLUSH;
    do {
      z.next_out = reinterpret_cast<Bytef*>(buffer.data());
      z.avail_out = static_cast<uInt>(buffer.size());
      deflate(&z, flush);
      out.append(buffer.data(), buffer.size() - z.avail_out);
    } while (z.avail_out == 0 || z.avail_in > 0);
  }
  deflateEnd(&z);
  return out;
}

// The files a case folder holds besides the copy of files/: what cannot be a small text file.
void generate_files(const fs::path& folder) {
  const std::string pdb = slurp(kTableFolder / "files" / "small.pdb");
  const std::string whole = gzip(pdb);
  write_text(folder / "small.pdb.gz", whole);
  write_text(folder / "truncated.pdb.gz", whole.substr(0, whole.size() * 6 / 10));
  std::string bad_crc = whole;
  bad_crc[bad_crc.size() - 8] = static_cast<char>(bad_crc[bad_crc.size() - 8] ^ 0x55);  // CRC-32's first byte
  write_text(folder / "bad-crc.pdb.gz", bad_crc);
  write_text(folder / "no-trailer.pdb.gz", whole.substr(0, whole.size() - 8));  // no CRC, no length
  write_text(folder / (kLatin1Name + ".obj"), slurp(kTableFolder / "files" / "open.obj"));
  write_text(folder / (kLatin1Name + ".pdb"), slurp(kTableFolder / "files" / "no-final-newline.pdb"));
}

// Every file under `folder` with its size: what a failing run must leave as it was.
std::map<std::string, std::uintmax_t> tree(const fs::path& folder) {
  std::map<std::string, std::uintmax_t> files;
  for (const auto& entry : fs::recursive_directory_iterator(folder)) {
    const std::string name = fs::relative(entry.path(), folder).string();
    if (name == "output.txt") continue;
    files[name] = entry.is_regular_file() ? entry.file_size() : 0;
  }
  return files;
}

struct ChildRun {
  bool timed_out = false;
  int signal = 0;
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

// The command under test: SPHEREMAP_CLI if set (to try another build's command on the table), else the one
// built with the tests (in build-asan/, scripts/test-sanitizers.sh, the one built with the sanitizers).
std::string cli_path() {
  const char* path = std::getenv("SPHEREMAP_CLI");
  return path != nullptr && *path != '\0' ? path : SPHEREMAP_CLI_PATH;
}

// Runs the command line in `folder` (no shell), killed after kTimeLimit.
ChildRun run_in(const fs::path& folder, const std::vector<std::string>& arguments) {
  std::vector<char*> argv;
  const std::string cli = cli_path();
  argv.push_back(const_cast<char*>(cli.c_str()));
  for (const auto& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const fs::path output = folder / "output.txt";
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setpgid(0, 0);
    const int fd = ::open(output.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0 || ::chdir(folder.c_str()) != 0) ::_exit(127);
    ::dup2(fd, 1);
    ::dup2(fd, 2);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  ChildRun run;
  const auto deadline = std::chrono::steady_clock::now() + kTimeLimit;
  int status = 0;
  for (;;) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (std::chrono::steady_clock::now() > deadline) {
      run.timed_out = true;
      ::kill(-pid, SIGKILL);
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  if (WIFSIGNALED(status)) run.signal = WTERMSIG(status);
  if (WIFEXITED(status)) run.exit_code = WEXITSTATUS(status);
  run.output = slurp(output);
  fs::remove(output);
  return run;
}

void PrintTo(const BadInputCase& c, std::ostream* out) { *out << "spheremap " << c.arguments; }

class BadInput : public testing_support::FolderTest, public testing::WithParamInterface<BadInputCase> {};

TEST_P(BadInput, Case) {
  const BadInputCase& c = GetParam();
  ASSERT_GE(c.exit_code, 0) << "cases.tsv: not five tab-separated fields: " << c.arguments;
  fs::copy(kTableFolder / "files", folder_, fs::copy_options::recursive);
  generate_files(folder_);
  // 80 MiB inflated: made only for its case (it takes a moment).
  if (c.arguments.find("bomb.pdb.gz") != std::string::npos) write_text(folder_ / "bomb.pdb.gz", gzip_of_zeros(80));
  std::vector<std::string> arguments;
  for (auto& argument : split(c.arguments, ' ')) {
    if (argument.empty()) continue;
    for (std::size_t at; (at = argument.find("{latin1}")) != std::string::npos;) argument.replace(at, 8, kLatin1Name);
    arguments.push_back(argument);
  }
  const auto before = tree(folder_);
  const ChildRun run = run_in(folder_, arguments);
  ASSERT_FALSE(run.timed_out) << "no exit within 30 s: spheremap " << c.arguments;
  ASSERT_EQ(run.signal, 0) << "killed by signal " << run.signal << " (" << strsignal(run.signal) << "):\n"
                           << run.output;
  EXPECT_EQ(run.exit_code, c.exit_code) << run.output;
  EXPECT_NE(run.output.find(c.names), std::string::npos) << "the message does not name '" << c.names << "':\n"
                                                         << run.output;
  EXPECT_NE(run.output.find(c.problem), std::string::npos) << "the message does not say '" << c.problem << "':\n"
                                                           << run.output;
  EXPECT_EQ(run.output.find("internal error"), std::string::npos) << run.output;
  // Under the sanitizers (their exit code may be the expected one): no report.
  for (const char* report : {"Sanitizer", "runtime error:"})
    EXPECT_EQ(run.output.find(report), std::string::npos) << run.output;
  EXPECT_TRUE(is_valid_utf8(run.output)) << "the output is not valid UTF-8:\n" << run.output;
  const auto after = tree(folder_);
  if (c.exit_code == 1 || c.exit_code == 2) {
    // A batch writes its summary (the failed rows) into its root, by design: the rest stays as it was.
    auto kept = after;
    if (arguments.front() == "batch")
      std::erase_if(kept, [](const auto& file) { return file.first.rfind(kBatchRoot, 0) == 0; });
    EXPECT_EQ(before, kept) << "a failing run left files behind or changed them";
  }
  for (const auto& [name, size] : after) {
    const auto extension = fs::path(name).extension();
    if (!before.count(name) && (extension == ".json" || extension == ".csv" || extension == ".jsonl"))
      EXPECT_TRUE(is_valid_utf8(slurp(folder_ / name))) << name << " is not valid UTF-8";
  }
}

INSTANTIATE_TEST_SUITE_P(Table, BadInput, testing::ValuesIn(read_cases()),
                         [](const testing::TestParamInfo<BadInputCase>& info) { return info.param.name; });

TEST(BadInputs, TheTableHasAtLeastSixtyCases) {
  const auto cases = read_cases();
  EXPECT_GE(cases.size(), 60u);
  std::set<std::string> names;
  for (const auto& c : cases) EXPECT_TRUE(names.insert(c.name).second) << "two cases named " << c.name;
}

}  // namespace
}  // namespace spheremap
