// The output folder of `spheremap map` (stage: pipeline): a folder that already holds an earlier run's
// outputs is refused, or with --force those outputs are replaced as a whole, so that old and new files
// never mix (a stale component-3/ beside a new run of two components).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace spheremap {

/// What `folder` holds of an earlier map run: the files of map_output_names(), `component-K/` folders
/// and temporaries an interrupted write left (`NAME.tmp-PID`), sorted, folders with a trailing '/'.
/// Other files are not listed. A missing folder holds nothing. Does not throw (but std::bad_alloc).
std::vector<std::string> earlier_map_outputs(const std::filesystem::path& folder);

/// Checks, before any work, that `folder` can take a map's outputs: it is a folder or can be created
/// (its nearest existing parent is a writable folder), and, unless `force`, it holds no earlier outputs.
/// Throws InputError naming the folder, the problem and the fix (another -o, or --force) otherwise.
void check_map_output_folder(const std::filesystem::path& folder, bool force);

/// Removes earlier_map_outputs(folder) (report.json first, so that a half-removed folder never looks
/// complete); other files stay. Throws InputError naming what cannot be removed.
void remove_map_outputs(const std::filesystem::path& folder);

}  // namespace spheremap
