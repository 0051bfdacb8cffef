#include "plot.hpp"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace dcad::cli {

namespace {

/// Runs gnuplot on the script, then removes it; "" or what went wrong.
std::string run_gnuplot(const std::string& script) {
  const int rc = std::system(("gnuplot " + script + " 2> " + script + ".err").c_str());
  std::ifstream err(script + ".err");
  std::stringstream why;
  why << err.rdbuf();
  std::remove((script + ".err").c_str());
  std::remove(script.c_str());
  return rc == 0 ? "" : "gnuplot failed: " + why.str();
}

std::string quoted(std::string s) {
  for (std::size_t i = 0; (i = s.find('\'', i)) != std::string::npos; i += 2) s.replace(i, 1, "''");
  return "'" + s + "'";
}

}  // namespace

std::vector<std::size_t> plot_columns(const std::vector<std::string>& header, const std::string& wanted) {
  std::vector<std::size_t> cols;
  if (wanted.empty()) {
    for (std::size_t j = 1; j < header.size(); ++j)
      if (header[j].rfind("q_", 0) == 0) cols.push_back(j + 1);
    if (cols.empty())
      for (std::size_t j = 1; j < header.size(); ++j) cols.push_back(j + 1);
    return cols;
  }
  std::istringstream in(wanted);
  for (std::string name; std::getline(in, name, ',');) {
    std::size_t j = 1;
    while (j < header.size() && header[j] != name) ++j;
    if (j == header.size()) {
      std::string all;
      for (std::size_t k = 1; k < header.size(); ++k) all += (k > 1 ? ", " : "") + header[k];
      throw std::invalid_argument("--plot-vars: expected variable names among " + all + ", found \"" + name + "\"");
    }
    cols.push_back(j + 1);
  }
  return cols;
}

std::string plot_png(const std::string& csv_file, const std::vector<std::string>& header,
                     const std::vector<std::size_t>& columns, const std::string& png, const std::string& title) {
  if (std::system("command -v gnuplot > /dev/null 2>&1") != 0)
    return "gnuplot not found (bash .ci/setup installs gnuplot-nox)";
  const std::string script = png + ".gp";
  {
    std::ofstream g(script);
    g << "set datafile separator ','\nset terminal png size 1000,600\nset output " << quoted(png) << "\nset title "
      << quoted(title) << " noenhanced\nset xlabel 't'\nset key outside right noenhanced\nset grid\nplot ";
    for (std::size_t i = 0; i < columns.size(); ++i)
      g << (i ? ", " : "") << quoted(csv_file) << " every ::1 using 1:" << columns[i] << " with lines title "
        << quoted(header[columns[i] - 1]);
    g << "\n";
  }
  return run_gnuplot(script);
}

std::string plot_check_png(const std::string& csv_file, const std::vector<std::string>& names,
                           const std::vector<double>& worst_t, const std::vector<double>& worst_found,
                           const std::string& png, const std::string& title) {
  if (std::system("command -v gnuplot > /dev/null 2>&1") != 0)
    return "gnuplot not found (bash .ci/setup installs gnuplot-nox)";
  const std::string script = png + ".gp";
  {
    std::ofstream g(script);
    g.precision(17);
    g << "set datafile separator ','\nset terminal png size 1000," << 200 + 300 * names.size() << "\nset output "
      << quoted(png) << "\nset multiplot layout " << names.size() << ",1 title " << quoted(title)
      << " noenhanced\nset xlabel 't'\nset key outside right noenhanced\nset grid\n";
    for (std::size_t k = 0; k < names.size(); ++k)
      g << "set title " << quoted(names[k]) << " noenhanced\nplot " << quoted(csv_file)
        << " every ::1 using 1:" << 2 * k + 3 << " with lines lw 2 title 'exact', " << quoted(csv_file)
        << " every ::1 using 1:" << 2 * k + 2 << " with points pt 7 ps 0.4 title 'simulator', '+' using (" << worst_t[k]
        << "):(" << worst_found[k] << ") every ::0::0 with points pt 6 ps 3 lw 2 title 'worst point'\n";
    g << "unset multiplot\n";
  }
  return run_gnuplot(script);
}

}  // namespace dcad::cli
