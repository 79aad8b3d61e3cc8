// docs/config.md against the declared keys: every key table of the page equals what the code declares,
// so a key added, removed or changed in code and not in the docs (or the other way round) fails here.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "mesodpd/config.hpp"
#include "schema/declared_tables.hpp"

namespace {

// The tables of the page, by the path of their "<!-- keys: PATH -->" marker.
std::map<std::string, std::string> tables_of_page(const std::string& file) {
  std::ifstream in(file);
  EXPECT_TRUE(in) << "cannot read " << file;
  std::map<std::string, std::string> out;
  std::string line, path;
  const std::string mark = "<!-- keys: ";
  while (std::getline(in, line)) {
    if (line.rfind(mark, 0) == 0) {
      path = line.substr(mark.size(), line.size() - mark.size() - 4);
      EXPECT_EQ(out.count(path), 0u) << "two markers for " << path;
      out[path];
    } else if (!path.empty() && line.rfind("|", 0) == 0) {
      out[path] += line + "\n";
    } else {
      path.clear();
    }
  }
  return out;
}

TEST(ConfigDocs, KeyTablesMatchTheDeclarations) {
  const auto page = tables_of_page(std::string(MESODPD_SOURCE_DIR) + "/docs/config.md");
  const auto declared = mesodpd::declared_tables();
  ASSERT_GE(declared.size(), 16u);
  for (const auto& t : declared) {
    SCOPED_TRACE("table " + t.path + " (tools/update_config_docs.py rewrites the page from the code)");
    const auto it = page.find(t.path);
    ASSERT_NE(it, page.end()) << "docs/config.md has no '<!-- keys: " << t.path << " -->' table";
    EXPECT_EQ(it->second, mesodpd::keys::markdown(t.rows));
  }
  for (const auto& [path, text] : page) {
    bool known = false;
    for (const auto& t : declared) known = known || t.path == path;
    EXPECT_TRUE(known) << "docs/config.md has a key table for '" << path << "', which the code does not declare";
  }
}

// The reader's key lists are the declarations: in every declared table an undeclared key is refused as
// unknown, naming its full key, and no declared key is (a value of the wrong type for every key, a
// date, gets a type error instead).
// The block under test is the first of its kind ([[species]] under test is the only species); the lines
// of its `minimal` that set the key under test are left out.
std::string config_with(const mesodpd::DeclaredTable& t, const std::string& line) {
  std::string text = t.path == "species" ? "" : "[[species]]\nname = \"A\"\ndensity = 3\n";
  if (t.path == "system")
    return text + "[system]\n" + (line.rfind("box ", 0) == 0 ? "" : "box = [10, 10, 10]\n") + line + "\n";
  text += "[system]\nbox = [10, 10, 10]\n";
  text += t.repeated ? "[[" + t.path + "]]\n" : "[" + t.path + "]\n";
  std::istringstream minimal(t.minimal);
  for (std::string m; std::getline(minimal, m);)
    if (line.rfind(m.substr(0, m.find(' ')) + " ", 0) != 0) text += m + "\n";
  return text + line + "\n";
}

TEST(ConfigDocs, TheReaderAcceptsExactlyTheDeclaredKeys) {
  for (const auto& t : mesodpd::declared_tables()) {
    try {
      mesodpd::parse_config(config_with(t, "no_such_key = 1"), "k.toml");
      ADD_FAILURE() << t.path << ": an undeclared key was accepted";
    } catch (const mesodpd::ConfigError& e) {
      EXPECT_EQ(e.key(), t.path + (t.repeated ? "[0]" : "") + ".no_such_key") << e.what();
      EXPECT_NE(std::string(e.what()).find("unknown key"), std::string::npos) << e.what();
    }
    for (const auto& row : t.rows) {
      try {
        mesodpd::parse_config(config_with(t, row.name + " = 1979-05-27"), "k.toml");
        ADD_FAILURE() << t.path << "." << row.name << ": a date was accepted";
      } catch (const mesodpd::ConfigError& e) {
        EXPECT_EQ(std::string(e.what()).find("unknown key"), std::string::npos) << e.what();
        EXPECT_EQ(e.key(), t.path + (t.repeated ? "[0]" : "") + "." + row.name) << e.what();
      }
    }
  }
}

}  // namespace
