// Quoting for the gnuplot scripts the commands write (tumble report, tumble sim2real) and the
// shell line that runs them.
#pragma once

#include <string>

namespace tumble::app {

// A POSIX shell single-quoted word: a quote becomes '\''.
inline std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (const char ch : s) {
    if (ch == '\'')
      q += "'\\''";
    else
      q += ch;
  }
  q += "'";
  return q;
}

// Gnuplot's single-quoted strings take no escapes; a quote is written twice.
inline std::string gnuplot_quote(const std::string& s) {
  std::string q = "'";
  for (const char ch : s) {
    q += ch;
    if (ch == '\'')
      q += '\'';
  }
  q += "'";
  return q;
}

}  // namespace tumble::app
