// The readers of the BOP dataset's JSON files: scene_camera.json (the
// images' intrinsics and world-to-camera poses) and models_info.json (the
// objects' diameters and symmetries). Both are objects keyed by an id
// written as a string ("0", "1", ...); lengths are millimetres.
#include <algorithm>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

#include "import/bop_files.h"
#include "io/json_tree.h"
#include "io/json_tree_reader.h"
#include "io/text_file.h"

namespace symba::import_internal {
namespace {

using io_internal::JsonPath;
using io_internal::JsonTree;
using io_internal::JsonTreeReader;
using io_internal::JsonType;
using Index = JsonTree::Index;

// R^T R may differ from I by this much (as in the results CSV).
constexpr double kRotationTolerance = 1e-2;

// An id key of the root object ("12").
Status Id(const JsonTreeReader& r,
          Index member,
          const JsonPath& path,
          int* id) {
  const std::string_view key = r.tree().Key(member);
  if (!internal::ParseInteger(key, id) || *id < 0) {
    return r.Fail(path, "expected a non-negative integer id as the key");
  }
  return Status::Ok();
}

// 9 numbers, row-major, forming a rotation.
Status Rotation(const JsonTreeReader& r,
                Index i,
                const JsonPath& path,
                Eigen::Matrix3d* R) {
  double v[9];
  Status status = r.Numbers(i, path, 9, v);
  if (!status.ok()) return status;
  *R = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(v);
  const double error =
      (R->transpose() * *R - Eigen::Matrix3d::Identity()).norm();
  if (!(error <= kRotationTolerance) || !(R->determinant() > 0.0)) {
    return r.Fail(path,
                  "not a rotation (|R^T R - I| = " + internal::Approx(error) +
                      ", det = " + internal::Approx(R->determinant()) + ")");
  }
  return Status::Ok();
}

Status Image(const JsonTreeReader& r,
             Index entry,
             const JsonPath& path,
             BopImage* image) {
  Status status = r.Object(entry, path);
  if (!status.ok()) return status;
  Index k = 0;
  status = r.Require(entry, path, "cam_K", "9 numbers, row-major", &k);
  if (!status.ok()) return status;
  const JsonPath k_path = path.Member("cam_K");
  double K[9];
  status = r.Numbers(k, k_path, 9, K);
  if (!status.ok()) return status;
  if (!(K[0] > 0.0) || !(K[4] > 0.0)) {
    return r.Fail(k_path, "fx and fy (elements 0 and 4) must be positive");
  }
  image->camera = PinholeIntrinsics{K[0], K[4], K[2], K[5]};
  const Index rotation = r.Find(entry, "cam_R_w2c");
  const Index translation = r.Find(entry, "cam_t_w2c");
  if ((rotation == 0) != (translation == 0)) {
    return r.Fail(path, "cam_R_w2c and cam_t_w2c go together");
  }
  if (rotation == 0) return Status::Ok();
  Eigen::Matrix3d R;
  status = Rotation(r, rotation, path.Member("cam_R_w2c"), &R);
  if (!status.ok()) return status;
  double t[3];
  status = r.Numbers(translation, path.Member("cam_t_w2c"), 3, t);
  if (!status.ok()) return status;
  image->T_cw = Rigid3d(Eigen::Quaterniond(R).normalized(),
                        Eigen::Vector3d(t[0], t[1], t[2]) / 1000.0);
  return Status::Ok();
}

Status DiscreteSymmetries(const JsonTreeReader& r,
                          Index array,
                          const JsonPath& path,
                          std::vector<Rigid3d>* out) {
  Status status = r.Array(array, path);
  int i = 0;
  for (Index e = r.tree().node(array).first; status.ok() && e != 0;
       e = r.tree().node(e).next, ++i) {
    const JsonPath element = path.Element(i);
    double m[16];
    status = r.Numbers(e, element, 16, m);
    if (!status.ok()) break;
    const Eigen::Matrix4d T =
        Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(m);
    const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
    const double error =
        (R.transpose() * R - Eigen::Matrix3d::Identity()).norm();
    if (!(error <= kRotationTolerance) || !(R.determinant() > 0.0) ||
        T.row(3) != Eigen::RowVector4d(0, 0, 0, 1)) {
      status = r.Fail(element,
                      "not a rigid transform (4x4 row-major, a rotation and "
                      "a last row 0 0 0 1)");
      break;
    }
    out->emplace_back(Eigen::Quaterniond(R).normalized(),
                      T.topRightCorner<3, 1>() / 1000.0);
  }
  return status;
}

Status ContinuousSymmetries(const JsonTreeReader& r,
                            Index array,
                            const JsonPath& path,
                            std::vector<BopContinuousSymmetry>* out) {
  Status status = r.Array(array, path);
  int i = 0;
  for (Index e = r.tree().node(array).first; status.ok() && e != 0;
       e = r.tree().node(e).next, ++i) {
    const JsonPath element = path.Element(i);
    status = r.Object(e, element);
    Index axis = 0;
    if (status.ok()) status = r.Require(e, element, "axis", "3 numbers", &axis);
    double a[3];
    if (status.ok()) status = r.Numbers(axis, element.Member("axis"), 3, a);
    if (!status.ok()) break;
    BopContinuousSymmetry symmetry;
    symmetry.axis = Eigen::Vector3d(a[0], a[1], a[2]);
    // stableNorm: an axis of 1e200 (or 1e-200) still has a direction.
    if (!(symmetry.axis.stableNorm() > 0.0)) {
      status = r.Fail(element.Member("axis"), "must not be zero");
      break;
    }
    symmetry.axis.stableNormalize();
    const Index offset = r.Find(e, "offset");
    if (offset != 0) {
      double o[3];
      status = r.Numbers(offset, element.Member("offset"), 3, o);
      if (!status.ok()) break;
      symmetry.offset = Eigen::Vector3d(o[0], o[1], o[2]) / 1000.0;
    }
    out->push_back(symmetry);
  }
  return status;
}

Status Model(const JsonTreeReader& r,
             Index entry,
             const JsonPath& path,
             BopModel* model) {
  Status status = r.Object(entry, path);
  if (!status.ok()) return status;
  const Index diameter = r.Find(entry, "diameter");
  if (diameter != 0) {
    status = r.Positive(diameter, path.Member("diameter"), &model->diameter);
    if (!status.ok()) return status;
    model->diameter /= 1000.0;
  }
  std::vector<Rigid3d> discrete;
  std::vector<BopContinuousSymmetry> continuous;
  const Index d = r.Find(entry, "symmetries_discrete");
  if (d != 0) {
    status =
        DiscreteSymmetries(r, d, path.Member("symmetries_discrete"), &discrete);
    if (!status.ok()) return status;
  }
  const Index c = r.Find(entry, "symmetries_continuous");
  if (c != 0) {
    status = ContinuousSymmetries(
        r, c, path.Member("symmetries_continuous"), &continuous);
    if (!status.ok()) return status;
  }
  model->prior = MapBopSymmetries(discrete, continuous, &model->note);
  return Status::Ok();
}

// Reads `path` and calls read(reader, member, member_path, id) for each
// member of its root object.
template <typename ReadMember>
Status ForEachIdMember(const std::string& path, ReadMember read) {
  JsonTree tree;
  Status status = io_internal::ReadJsonFile(path, &tree);
  if (!status.ok()) return status;
  const JsonTreeReader r(path, 0, tree);
  const JsonPath root;
  status = r.Object(0, root);
  for (Index m = tree.node(0).first; status.ok() && m != 0;
       m = tree.node(m).next) {
    const JsonPath member = root.QuotedMember(tree.Key(m));
    int id = 0;
    status = Id(r, m, member, &id);
    if (status.ok()) status = read(r, m, member, id);
  }
  return status;
}

}  // namespace

Status ReadBopSceneCamera(const std::string& path,
                          std::vector<BopImage>* images) {
  images->clear();
  Status status = ForEachIdMember(
      path,
      [&](const JsonTreeReader& r, Index m, const JsonPath& where, int id) {
        BopImage image;
        image.im_id = id;
        Status s = Image(r, m, where, &image);
        if (s.ok()) images->push_back(image);
        return s;
      });
  if (!status.ok()) return status;
  if (images->empty()) return Status::Error(path + ": no images");
  std::sort(
      images->begin(), images->end(), [](const BopImage& a, const BopImage& b) {
        return a.im_id < b.im_id;
      });
  for (std::size_t i = 1; i < images->size(); ++i) {
    if ((*images)[i].im_id == (*images)[i - 1].im_id) {
      return Status::Error(path + ": image " +
                           std::to_string((*images)[i].im_id) +
                           " appears twice");
    }
  }
  return Status::Ok();
}

Status ReadBopModelsInfo(const std::string& path,
                         std::map<int, BopModel>* models) {
  models->clear();
  return ForEachIdMember(
      path,
      [&](const JsonTreeReader& r, Index m, const JsonPath& where, int id) {
        if (models->count(id) != 0) {
          return r.Fail(where, "object id appears twice");
        }
        return Model(r, m, where, &(*models)[id]);
      });
}

}  // namespace symba::import_internal
