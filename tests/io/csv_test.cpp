// Delimited tables: quote-aware reading, RFC 4180 fields, numbers that read back, UTF-8 repair.
#include "spheremap/io/csv.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "spheremap/error.hpp"

namespace spheremap {
namespace {

TEST(Csv, ReadsQuotedFieldsCommentsAndLineNumbers) {
  const auto records = read_delimited(
      "\xEF\xBB\xBF"
      "a,b\r\n# comment\n\n\"x, y\",\"say \"\"hi\"\"\"\n1,\"two\nlines\"\n3,\n",
      ',', "t.csv");
  ASSERT_EQ(records.size(), 4u);
  EXPECT_EQ(records[0].fields, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(records[1].line, 4);
  EXPECT_EQ(records[1].fields, (std::vector<std::string>{"x, y", "say \"hi\""}));
  EXPECT_EQ(records[2].fields, (std::vector<std::string>{"1", "two\nlines"}));
  EXPECT_EQ(records[3].line, 7);
  EXPECT_EQ(records[3].fields, (std::vector<std::string>{"3", ""}));
  EXPECT_EQ(read_delimited("a\tb\n", '\t', "t.tsv")[0].fields.size(), 2u);
}

TEST(Csv, UnclosedQuoteNamesTheLine) {
  try {
    read_delimited("a,b\n1,\"open\n", ',', "bad.csv");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.csv"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find('2'), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_delimited("\"a\"b,c\n", ',', "bad.csv"), InputError);
}

TEST(Csv, FieldsAndNumbers) {
  EXPECT_EQ(csv_field("plain"), "plain");
  EXPECT_EQ(csv_field("a,b"), "\"a,b\"");
  EXPECT_EQ(csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(csv_field(" padded"), "\" padded\"");
  EXPECT_EQ(csv_number(std::numeric_limits<double>::quiet_NaN()), "");
  EXPECT_EQ(csv_number(0.1), "0.1");
  EXPECT_EQ(std::stod(csv_number(1.0 / 3)), 1.0 / 3);
  EXPECT_EQ(csv_number(-std::numeric_limits<double>::infinity()), "-inf");
  EXPECT_EQ(valid_utf8("ok \xC3\xA9"), "ok \xC3\xA9");
  EXPECT_EQ(valid_utf8("bad \xFF!"), "bad \xEF\xBF\xBD!");
}

}  // namespace
}  // namespace spheremap
