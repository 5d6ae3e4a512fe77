#pragma once
// One number formatter for tables, reports and messages (the CLI, docs/fidelity.md, residual reports,
// importer provenance): a printf spec for one double, and a placeholder where the value is not finite,
// so a table never prints "nan" or "inf".
#include <string>

namespace sb {

// format_number(1.23456) == "1.235"; format_number(2.0, "%.1f") == "2.0"; format_number(NAN) == "-".
std::string format_number(double v, const char* spec = "%.3f", const char* not_finite = "-");

}  // namespace sb
