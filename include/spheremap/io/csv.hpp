// Delimited text tables (stage: io): reading CSV/TSV records quote-aware, writing RFC 4180 fields.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "spheremap/text.hpp"  // valid_utf8

namespace spheremap {

/// One record of a delimited file and the line it starts on (1-based).
struct DelimitedRecord {
  std::int64_t line = 0;
  std::vector<std::string> fields;
};

/// Splits `text` into records. The dialect: fields separated by `delimiter` (',' or '\t'); records end at LF,
/// CRLF or the end of the text; a field that starts with '"' is quoted (RFC 4180): it runs to the next lone '"',
/// may hold delimiters and line breaks, and "" stands for one '"'. Spaces around an unquoted field are part of
/// it (callers trim). Blank lines and lines whose first character is '#' are skipped; a UTF-8 byte-order mark
/// at the start is dropped. `name` names the text in messages.
/// Throws InputError naming `name` and the line for a quoted field that never closes or is followed by other
/// characters than a delimiter or the end of the record.
std::vector<DelimitedRecord> read_delimited(std::string_view text, char delimiter, const std::string& name);

/// One field of an RFC 4180 CSV file: valid_utf8(text), quoted (quotes doubled) when it holds a comma, a
/// quote, a line break, or leading or trailing white space. Never throws (but std::bad_alloc).
std::string csv_field(std::string_view text);

/// A number for a CSV file: the shortest text that reads back as the same double; empty for NaN (no value);
/// "inf" / "-inf" for infinities. Never throws (but std::bad_alloc).
std::string csv_number(double value);

}  // namespace spheremap
