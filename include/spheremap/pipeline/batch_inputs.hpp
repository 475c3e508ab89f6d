// The inputs of a batch (stage: pipeline): command-line arguments expanded into files, and the name of
// each one's output folder.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace spheremap {

/// True for the files a batch takes from a folder: meshes (.obj .off .ply .stl, any case) and
/// structures (is_structure_file: .pdb .ent .cif .mmcif .pqr, optionally .gz). Looks at the name only.
bool is_batch_input_file(const std::filesystem::path& path);

/// Expands command-line arguments into input files, in order, each file once (the first occurrence
/// wins; compared after std::filesystem::weakly_canonical):
/// - an existing folder: its mesh and structure files (is_batch_input_file), not recursive, hidden
///   files (name starting with '.') left out, sorted by file name (byte order);
/// - `@LIST`, or an existing file whose name ends in `.txt`: a list, one argument per line (blank lines
///   and lines starting with '#' ignored, surrounding spaces trimmed), each expanded by these same rules;
///   relative paths are relative to the list's folder; lists may include lists (8 levels at most);
/// - an argument that is not an existing path but contains `*`, `?` or `[`: a glob(3) pattern; its
///   matches, sorted (byte order), are expanded like arguments (as if the shell had expanded it:
///   files are taken whatever their extension, folders give their files);
/// - anything else: a file, taken as given, even if missing or of an unknown format (its run then
///   fails with the reader's message, like `spheremap map`).
/// Throws InputError if a list or folder cannot be read, lists nest too deeply, or the result is empty.
std::vector<std::filesystem::path> expand_batch_inputs(const std::vector<std::string>& arguments);

struct BatchInput {
  std::filesystem::path path;
  std::string name;  // its output folder, under the output root
};

/// Output folder names, unique under the root: the file name without `.gz` and without its extension
/// (`1crn.cif.gz` -> `1crn`). Inputs whose names clash (compared case-insensitively, also with the
/// root's own files summary.csv, summary.jsonl and batch.json) all use their whole file name instead
/// (`1abc.pdb`, `1abc.cif`); if those still clash (the same file name in two folders), the second,
/// third, ... in input order get `~2`, `~3`, ... appended. Names therefore depend on the set of inputs,
/// not on their order, except for that last rule. Does not throw (but std::bad_alloc).
std::vector<BatchInput> name_batch_inputs(const std::vector<std::filesystem::path>& paths);

/// The files a batch writes into its output root, besides one folder per input.
inline constexpr const char* kSummaryCsvFile = "summary.csv";
inline constexpr const char* kSummaryJsonlFile = "summary.jsonl";
inline constexpr const char* kBatchManifestFile = "batch.json";
/// Those three names: no input's folder may take one of them.
const std::vector<std::string>& batch_root_file_names();

}  // namespace spheremap
