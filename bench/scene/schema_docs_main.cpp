// Prints each README field table between its markers, for scripts/update-readme-tables.sh.
#include <cstdio>

#include "tessera/scene/schema/docs.hpp"

int main() {
  const auto block = [](const char* name, const std::string& table) {
    std::printf("<!-- fields:%s -->\n%s<!-- /fields:%s -->\n", name, table.c_str(), name);
  };
  block("shapes", tessera::schema::shape_table_markdown());
  block("materials", tessera::schema::material_table_markdown());
  block("sections", tessera::schema::section_table_markdown());
  return 0;
}
