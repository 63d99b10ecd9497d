#include "symba/export/bop_results_csv.h"

#include <Eigen/Core>

#include "export/bop_units.h"
#include "symba/io/file_output.h"
#include "symba/io/format_double.h"

namespace symba {
namespace {

using internal::kMillimetresPerMetre;

// `count` numbers separated by single spaces.
void AppendNumbers(const double* values, int count, std::string* out) {
  for (int i = 0; i < count; ++i) {
    if (i > 0) out->push_back(' ');
    AppendDouble(values[i], out);
  }
}

void AppendRow(const BopResult& row, std::string* out) {
  out->append(std::to_string(row.scene_id)).push_back(',');
  out->append(std::to_string(row.im_id)).push_back(',');
  out->append(std::to_string(row.obj_id)).push_back(',');
  AppendDouble(row.score, out);
  out->push_back(',');
  // Eigen matrices are column-major: the transpose's storage is R row-major.
  const Eigen::Matrix3d R_transposed = row.T_co.RotationMatrix().transpose();
  AppendNumbers(R_transposed.data(), 9, out);
  out->push_back(',');
  const Eigen::Vector3d t_mm = kMillimetresPerMetre * row.T_co.t;
  AppendNumbers(t_mm.data(), 3, out);
  out->push_back(',');
  AppendDouble(row.time, out);
  out->push_back('\n');
}

}  // namespace

std::string FormatBopResultsCsv(const std::vector<BopResult>& rows) {
  std::string text = "scene_id,im_id,obj_id,score,R,t,time\n";
  for (const BopResult& row : rows) AppendRow(row, &text);
  return text;
}

Status WriteBopResultsCsv(const std::string& path,
                          const std::vector<BopResult>& rows) {
  return WriteFileAtomically(path, FormatBopResultsCsv(rows));
}

}  // namespace symba
