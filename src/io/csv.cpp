#include "spheremap/io/csv.hpp"

#include <cmath>

#include <fmt/format.h>

#include "spheremap/error.hpp"

namespace spheremap {
namespace {

class RecordReader {
 public:
  RecordReader(std::string_view text, char delimiter, const std::string& name)
      : text_(text), delimiter_(delimiter), name_(name) {
    if (text_.substr(0, 3) == "\xEF\xBB\xBF") text_.remove_prefix(3);
  }

  std::vector<DelimitedRecord> read() {
    std::vector<DelimitedRecord> records;
    while (at_ < text_.size()) {
      const std::int64_t first_line = line_;
      if (text_[at_] == '#' || text_[at_] == '\n' || text_.substr(at_, 2) == "\r\n") {
        skip_line();
        continue;
      }
      DelimitedRecord record{first_line, {}};
      while (true) {
        record.fields.push_back(field());
        if (at_ >= text_.size()) break;
        if (text_[at_] == delimiter_) {
          ++at_;
          continue;
        }
        end_of_line();
        break;
      }
      records.push_back(std::move(record));
    }
    return records;
  }

 private:
  void skip_line() {
    while (at_ < text_.size() && text_[at_] != '\n') ++at_;
    if (at_ < text_.size()) ++at_;
    ++line_;
  }
  void end_of_line() {
    if (text_[at_] == '\r') ++at_;
    if (at_ < text_.size() && text_[at_] == '\n') ++at_;
    ++line_;
  }
  bool at_record_end() const { return at_ >= text_.size() || text_[at_] == '\n' || text_.substr(at_, 2) == "\r\n"; }

  std::string field() {
    std::string value;
    if (at_ < text_.size() && text_[at_] == '"') return quoted();
    while (at_ < text_.size() && text_[at_] != delimiter_ && !at_record_end()) value += text_[at_++];
    return value;
  }

  std::string quoted() {
    const std::int64_t opened = line_;
    std::string value;
    ++at_;
    while (true) {
      if (at_ >= text_.size())
        throw InputError(
            fmt::format("{}:{}: a quoted field opened here never closes; add the closing '\"'", name_, opened));
      const char c = text_[at_++];
      if (c == '"') {
        if (at_ < text_.size() && text_[at_] == '"') {
          value += '"';
          ++at_;
          continue;
        }
        break;
      }
      if (c == '\n') ++line_;
      value += c;
    }
    if (at_ < text_.size() && text_[at_] != delimiter_ && !at_record_end())
      throw InputError(
          fmt::format("{}:{}: text after a quoted field's closing '\"'; quote the whole field, with "
                      "quotes inside doubled (\"\")",
                      name_, line_));
    return value;
  }

  std::string_view text_;
  char delimiter_;
  const std::string& name_;
  std::size_t at_ = 0;
  std::int64_t line_ = 1;
};

}  // namespace

std::vector<DelimitedRecord> read_delimited(std::string_view text, char delimiter, const std::string& name) {
  return RecordReader(text, delimiter, name).read();
}

std::string csv_field(std::string_view text) {
  std::string value = valid_utf8(text);
  const auto is_space = [](char c) { return c == ' ' || c == '\t'; };
  const bool quote = value.find_first_of(",\"\r\n") != std::string::npos ||
                     (!value.empty() && (is_space(value.front()) || is_space(value.back())));
  if (!quote) return value;
  std::string quoted = "\"";
  for (const char c : value) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + '"';
}

std::string csv_number(double value) {
  if (std::isnan(value)) return {};
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  return fmt::format("{}", value);
}

}  // namespace spheremap
