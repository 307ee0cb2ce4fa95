#pragma once
#include <string>

namespace tessera::schema {

// The README's field tables, made from the kind declarations (schema_docs_test checks the
// README holds exactly these, between <!-- fields:NAME --> and <!-- /fields:NAME -->).
std::string shape_table_markdown();     // NAME = shapes
std::string material_table_markdown();  // NAME = materials
std::string section_table_markdown();   // NAME = sections: camera, background, render

}  // namespace tessera::schema
