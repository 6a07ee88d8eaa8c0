// Numbers as text: the one place patlab formats a number for a message, a table, a CSV or JSON
// cell (docs/architecture.md, "Numbers as text"). printf semantics throughout, computed with
// std::to_chars: the text of the "C" locale whatever setlocale() or a stream's locale says, so
// results files are the same bytes under any locale.
#pragma once

#include <string>

namespace patlab {

// A number in an error or report message: up to 12 significant digits, "nan", "inf", "-inf".
std::string FormatNumber(double value);

// printf "%.*g": `digits` significant digits (CSV and JSON cells of results files).
std::string FormatSignificant(double value, int digits);

// printf "%.*f": `decimals` digits after the point (tables meant for people).
std::string FormatFixed(double value, int decimals);

// The shortest "%.15g".."%.17g" text that reads back as the same double.
std::string FormatRoundTrip(double value);

// printf into a std::string; for table rows that mix several numbers and fields. patlab's own
// implementation of the printf conversions (flags - + space 0, width, precision, * and the length
// modifiers; d i u x X o c s f F e E g G %; no '#' forms): the floating-point ones go through
// std::to_chars, so the text never depends on the locale.
[[gnu::format(printf, 1, 2)]] std::string StringPrintf(const char* format, ...);

}  // namespace patlab
