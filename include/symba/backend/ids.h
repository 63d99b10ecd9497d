// The backend's identifiers, one type per kind. A front end chooses the
// keyframe and point ids (keyframe ids strictly increasing, point ids stable
// across keyframes); the backend chooses the object ids (0, 1, 2, ... in
// creation order, never reused; -1 in an assignment: no object).
#ifndef SYMBA_BACKEND_IDS_H_
#define SYMBA_BACKEND_IDS_H_

#include <cstdint>

namespace symba {

using KeyframeId = std::int64_t;
using PointId = std::int64_t;
using ObjectId = int;

}  // namespace symba

#endif  // SYMBA_BACKEND_IDS_H_
