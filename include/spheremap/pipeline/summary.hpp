// The summary of a batch (stage: pipeline): one row per run, built from the run folders only (so that a
// resumed batch gives the same summary as an uninterrupted one, up to the measured timings of what was
// redone), written as summary.csv and summary.jsonl; and the batch's exit code.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "spheremap/pipeline/batch_inputs.hpp"
#include "spheremap/sphere/map.hpp"

namespace spheremap {

/// The columns of summary.csv (and the keys of each summary.jsonl line), in order (their meaning:
/// docs/batch.md). Does not throw (but std::bad_alloc).
const std::vector<std::string>& summary_columns();

/// One row: an object with exactly summary_columns() as keys (null where not applicable), built from
/// the run folder only (read_run_folder: report.json or error.json; status "pending" and nulls when
/// neither exists). Does not throw (but std::bad_alloc).
nlohmann::ordered_json summary_row(const BatchInput& input, Weights weights, const std::filesystem::path& root,
                                   const std::filesystem::path& folder);

/// All rows: inputs in order, then weightings in order. Does not throw (but std::bad_alloc).
std::vector<nlohmann::ordered_json> build_summary(const std::filesystem::path& root,
                                                  const std::vector<BatchInput>& inputs,
                                                  const std::vector<Weights>& weights);

/// summary.csv text: a header line, then one line per row; RFC 4180 quoting (a field holding a comma,
/// a double quote, a line break or leading/trailing spaces is quoted, quotes doubled), LF line ends,
/// UTF-8; numbers as in JSON (shortest text that reads back the same double), null as an empty field.
/// Columns missing from a row are empty. Does not throw (but std::bad_alloc).
std::string summary_csv(const std::vector<nlohmann::ordered_json>& rows);
/// summary.jsonl text: one JSON object per line (the same keys and values as the CSV); invalid UTF-8
/// replaced. Does not throw (but std::bad_alloc).
std::string summary_jsonl(const std::vector<nlohmann::ordered_json>& rows);

/// Builds the summary from the folders and writes summary.csv and summary.jsonl into `root`, each
/// atomically. Returns the rows. Throws InputError if a file cannot be written.
std::vector<nlohmann::ordered_json> write_batch_summary(const std::filesystem::path& root,
                                                        const std::vector<BatchInput>& inputs,
                                                        const std::vector<Weights>& weights);

/// The exit code of a batch from its rows: the first of 4 (internal error), 1 (unreadable input),
/// 2 (refused mesh), 3 (not certified) that some row has, else 0. A pending row counts as 4 (a run
/// that could not record its result); an interrupted batch is the caller's business (130).
/// Precondition: rows as summary_row makes them (else nlohmann::json exceptions).
int batch_exit_code(const std::vector<nlohmann::ordered_json>& rows);

}  // namespace spheremap
