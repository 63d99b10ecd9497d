"""symba: the object-SLAM backend for symmetric objects, from Python.

Poses are NumPy float64 arrays: one pose is (7,) ``[tx, ty, tz, qx, qy, qz,
qw]`` (translation, then a Hamilton quaternion with the scalar *last*, as in
the log format and TUM files), N poses are (N, 7). Pose arguments also take
4 x 4 homogeneous matrices, (4, 4) or (N, 4, 4). Library errors raise
:class:`symba.Error` (a RuntimeError) with the C++ message unchanged; input
arrays of the wrong dtype or shape, or with NaN/Inf, raise ValueError naming
the argument. docs/python.md has the whole API.
"""

import numpy as _np

from ._symba import (
    AngleCluster,
    Assignment,
    Backend,
    BackendOptions,
    BackendStatistics,
    BopImportReport,
    BopSource,
    Categorization,
    CategorizationDiagnostics,
    CategorizationOptions,
    ClassNoise,
    ClassPrior,
    CovarianceNoiseGroup,
    Detection,
    Error,
    EdgeWeights,
    HypothesisScatter,
    Keyframe,
    LogHeader,
    LogReader,
    LogWriter,
    LoopClosure,
    LoopClosureReport,
    LoopObjectPair,
    MapObject,
    MixtureOptions,
    MotionClaimGroup,
    MotionNoise,
    NoiseClaims,
    NoiseSamples,
    Odometry,
    PinholeIntrinsics,
    RelocalizationReport,
    ReplayResult,
    SimulatedObject,
    Simulation,
    SolveReport,
    Trajectory,
    categorize,
    import_bop,
    import_bop_to_log,
    import_tum,
    import_tum_to_log,
    parse_class_prior,
    read_log,
    replay,
    scene_names,
    simulate,
    write_log,
)

Error.__module__ = __name__

__all__ = [
    "AngleCluster",
    "Assignment",
    "Backend",
    "BackendOptions",
    "BackendStatistics",
    "BopImportReport",
    "BopSource",
    "Categorization",
    "CategorizationDiagnostics",
    "CategorizationOptions",
    "ClassNoise",
    "ClassPrior",
    "CovarianceNoiseGroup",
    "Detection",
    "Error",
    "EdgeWeights",
    "HypothesisScatter",
    "Keyframe",
    "LogHeader",
    "LogReader",
    "LogWriter",
    "LoopClosure",
    "LoopClosureReport",
    "LoopObjectPair",
    "MapObject",
    "MixtureOptions",
    "MotionClaimGroup",
    "MotionNoise",
    "NoiseClaims",
    "NoiseSamples",
    "Odometry",
    "PinholeIntrinsics",
    "RelocalizationReport",
    "ReplayResult",
    "SimulatedObject",
    "Simulation",
    "SolveReport",
    "Trajectory",
    "categorize",
    "import_bop",
    "import_bop_to_log",
    "import_tum",
    "import_tum_to_log",
    "parse_class_prior",
    "pose_matrices",
    "pose_vectors",
    "read_log",
    "replay",
    "scene_names",
    "simulate",
    "write_log",
]


def pose_matrices(poses):
    """(N, 7) or (7,) poses [tx, ty, tz, qx, qy, qz, qw] as (N, 4, 4) or
    (4, 4) homogeneous matrices (the quaternions are normalised first)."""
    p = _np.asarray(poses, dtype=_np.float64)
    if p.shape[-1:] != (7,) or p.ndim not in (1, 2):
        raise ValueError(
            f"poses: expected shape (7,) or (N, 7), got shape {p.shape}")
    single = p.ndim == 1
    p = p.reshape(-1, 7)
    q = p[:, 3:7] / _np.linalg.norm(p[:, 3:7], axis=1, keepdims=True)
    x, y, z, w = q[:, 0], q[:, 1], q[:, 2], q[:, 3]
    m = _np.zeros((p.shape[0], 4, 4))
    m[:, 0, 0] = 1 - 2 * (y * y + z * z)
    m[:, 0, 1] = 2 * (x * y - z * w)
    m[:, 0, 2] = 2 * (x * z + y * w)
    m[:, 1, 0] = 2 * (x * y + z * w)
    m[:, 1, 1] = 1 - 2 * (x * x + z * z)
    m[:, 1, 2] = 2 * (y * z - x * w)
    m[:, 2, 0] = 2 * (x * z - y * w)
    m[:, 2, 1] = 2 * (y * z + x * w)
    m[:, 2, 2] = 1 - 2 * (x * x + y * y)
    m[:, :3, 3] = p[:, :3]
    m[:, 3, 3] = 1.0
    return m[0] if single else m


def pose_vectors(matrices):
    """(N, 4, 4) or (4, 4) homogeneous matrices as (N, 7) or (7,) poses
    [tx, ty, tz, qx, qy, qz, qw] with qw >= 0."""
    m = _np.asarray(matrices, dtype=_np.float64)
    if m.shape[-2:] != (4, 4) or m.ndim not in (2, 3):
        raise ValueError(
            f"matrices: expected shape (4, 4) or (N, 4, 4), got shape {m.shape}")
    single = m.ndim == 2
    m = m.reshape(-1, 4, 4)
    out = _np.empty((m.shape[0], 7))
    out[:, :3] = m[:, :3, 3]
    for i, r in enumerate(m[:, :3, :3]):
        # Shepperd's method: the largest of w, x, y, z is computed first.
        t = _np.trace(r)
        d = _np.array([t, r[0, 0], r[1, 1], r[2, 2]])
        k = int(_np.argmax(d))
        if k == 0:
            s = 2.0 * _np.sqrt(1.0 + t)
            q = [(r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s,
                 (r[1, 0] - r[0, 1]) / s, 0.25 * s]
        elif k == 1:
            s = 2.0 * _np.sqrt(1.0 + r[0, 0] - r[1, 1] - r[2, 2])
            q = [0.25 * s, (r[0, 1] + r[1, 0]) / s, (r[0, 2] + r[2, 0]) / s,
                 (r[2, 1] - r[1, 2]) / s]
        elif k == 2:
            s = 2.0 * _np.sqrt(1.0 + r[1, 1] - r[0, 0] - r[2, 2])
            q = [(r[0, 1] + r[1, 0]) / s, 0.25 * s, (r[1, 2] + r[2, 1]) / s,
                 (r[0, 2] - r[2, 0]) / s]
        else:
            s = 2.0 * _np.sqrt(1.0 + r[2, 2] - r[0, 0] - r[1, 1])
            q = [(r[0, 2] + r[2, 0]) / s, (r[1, 2] + r[2, 1]) / s, 0.25 * s,
                 (r[1, 0] - r[0, 1]) / s]
        q = _np.array(q)
        if q[3] < 0:
            q = -q
        out[i, 3:] = q / _np.linalg.norm(q)
    return out[0] if single else out
