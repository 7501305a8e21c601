// Console presentation shared by the commands: Markdown tables with aligned columns.
#pragma once

#include <string>

namespace scw::cli {

/// `markdown` with every table's columns padded to a common width (numbers right-aligned, with
/// a `---:` separator), so that the table reads as a table on a terminal and stays valid
/// Markdown. Lines that are not table rows are kept as they are.
std::string AlignMarkdownTables(const std::string& markdown);

}  // namespace scw::cli
