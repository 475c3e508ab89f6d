// --values files: the dialect, matching to atoms, and every kind of bad input named by file and line.
#include "spheremap/properties/values_file.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "../test_support.hpp"
#include "spheremap/error.hpp"

namespace spheremap {
namespace {

using testing_support::write_text;

class ValuesFile : public testing_support::FolderTest {
 protected:
  std::filesystem::path write(const std::string& text) {
    const auto path = folder_ / "values.csv";
    write_text(path, text);
    return path;
  }
  // The message of the InputError that reading (and matching) `text` throws; empty if none.
  std::string error_of(const std::string& text) {
    try {
      match_values(read_values_file(write(text)), atoms_);
    } catch (const InputError& e) {
      return e.what();
    }
    return {};
  }
  std::vector<Atom> atoms_ = [] {
    std::vector<Atom> atoms;
    for (const auto& [chain, number, insertion, name] : std::vector<std::tuple<std::string, int, char, std::string>>{
             {"A", 1, ' ', "N"}, {"A", 1, ' ', "CA"}, {"A", 2, ' ', "CA"}, {"A", 2, 'B', "CA"}, {"B", 5, ' ', "CA"}}) {
      Atom a;
      a.chain = chain, a.residue_number = number, a.insertion_code = insertion, a.name = name, a.residue_name = "GLY";
      atoms.push_back(a);
    }
    return atoms;
  }();
};

TEST_F(ValuesFile, ResidueAndAtomRowsQuotedAndTabSeparated) {
  const auto table = read_values_file(
      write("# conservation and pLDDT\nChain,ResNum,icode,atom,Conservation,plddt\nA,1,,,0.5,90\nA,1,,CA,0.7,\n"
            "\"A\",2B,,,NA,70\nB,6,,,1,1\n"));
  EXPECT_EQ(table.columns, (std::vector<std::string>{"conservation", "plddt"}));
  const auto columns = match_values(table, atoms_);
  ASSERT_EQ(columns.size(), 2u);
  const auto& c = columns[0].per_atom;
  EXPECT_EQ(c[0], 0.5);           // residue row
  EXPECT_EQ(c[1], 0.7);           // the atom row is more specific
  EXPECT_TRUE(std::isnan(c[2]));  // A:2 has no row
  EXPECT_TRUE(std::isnan(c[3]));  // NA
  EXPECT_TRUE(std::isnan(c[4]));
  EXPECT_EQ(columns[1].per_atom[3], 70);
  EXPECT_TRUE(std::isnan(columns[1].per_atom[1]));  // empty cell
  EXPECT_EQ(columns[0].rows, 4);
  EXPECT_EQ(columns[0].rows_unmatched, 1);  // B:6
  EXPECT_EQ(columns[0].atoms_without_value, 3);

  const auto tsv = read_values_file(write("chain\tresidue_number\tscore\nA\t2\t-1.5\n"));
  EXPECT_EQ(match_values(tsv, atoms_)[0].per_atom[2], -1.5);
}

TEST_F(ValuesFile, BadInputNamesFileLineAndProblem) {
  EXPECT_NE(error_of("chain,residue_number,score\nC,1,1\n").find("values.csv:2: chain 'C'"), std::string::npos);
  EXPECT_NE(error_of("chain,residue_number,score\nA,1,high\n").find("values.csv:2: column 'score': 'high'"),
            std::string::npos);
  EXPECT_NE(error_of("chain,score\nA,1\n").find("needs a 'chain' and a 'residue_number'"), std::string::npos);
  EXPECT_NE(error_of("chain,residue_number\nA,1\n").find("no value column"), std::string::npos);
  EXPECT_NE(error_of("chain,residue_number,score\nA,1\n").find("values.csv:2: 2 fields"), std::string::npos);
  EXPECT_NE(error_of("chain,residue_number,score\nA,x1,1\n").find("not an integer"), std::string::npos);
  EXPECT_NE(error_of("chain,residue_number,score\nA,1,1\nA,1,2\n").find("values.csv:3: A:1 has a row already"),
            std::string::npos);
  EXPECT_NE(error_of("chain,residue_number,2nd\nA,1,1\n").find("cannot name a property"), std::string::npos);
  EXPECT_NE(error_of("").find("no header"), std::string::npos);
}

}  // namespace
}  // namespace spheremap
