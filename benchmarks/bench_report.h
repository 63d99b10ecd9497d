// Small helpers the benchmark programs share for their markdown reports:
// number formatting, means and medians, the provenance lines (command,
// machine, date) and writing a text file.
#ifndef SYMBA_BENCHMARKS_BENCH_REPORT_H_
#define SYMBA_BENCHMARKS_BENCH_REPORT_H_

#include <string>
#include <vector>

#include "symba/common/status.h"

namespace symba::bench {

// `value` with `decimals` decimals, "n/a" when not finite.
std::string Fixed(double value, int decimals);

// Mean / median of the finite values (NaN if none).
double Mean(const std::vector<double>& values);
double Median(std::vector<double> values);

// "1 object", "2 objects".
std::string Count(int n, const std::string& noun);

// Writes `text` to `path`; "PATH: cannot write".
Status WriteText(const std::string& path, const std::string& text);

// docs/results.md has two authors: symba-bench writes the simulated scenes
// and symba-real-bench the last section, "## Real data" (kRealDataHeading).
inline constexpr const char* kRealDataHeading = "## Real data\n";
// The part of the file at `path` from the line `heading` on ("" if the
// file or the heading is missing).
std::string TailFrom(const std::string& path, const std::string& heading);
// Writes `head` followed by the file's tail from `heading` (kept).
Status WriteKeepingTail(const std::string& path,
                        const std::string& head,
                        const std::string& heading);
// Replaces the file's tail from `heading` (or appends) with `section`.
Status ReplaceTail(const std::string& path,
                   const std::string& heading,
                   const std::string& section);

// Replaces the file's part from the line `heading` up to the next line
// that starts with `next` (or to the end) with `section`; appends `section`
// when the heading is missing.
Status ReplaceSection(const std::string& path,
                      const std::string& heading,
                      const std::string& next,
                      const std::string& section);

// The command line, space-separated.
std::string Command(int argc, char** argv);
// "CPU model, N hardware threads, OS release machine".
std::string Machine();
// "YYYY-MM-DD HH:MM UTC", now.
std::string UtcDate();

}  // namespace symba::bench

#endif  // SYMBA_BENCHMARKS_BENCH_REPORT_H_
