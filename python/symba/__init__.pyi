# Type stubs of the symba Python module (docs/python.md). Poses are float64
# arrays [tx, ty, tz, qx, qy, qz, qw] (quaternion scalar last), shape (7,) or
# (N, 7); pose arguments also take 4 x 4 matrices, (4, 4) or (N, 4, 4).
# tests/python/test_stubs.py checks that these stubs name everything the
# module has.
from typing import Any, Iterator, Literal, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

Float64Array = npt.NDArray[np.float64]
Int64Array = npt.NDArray[np.int64]
ArrayLike = npt.ArrayLike
SymmetryName = Literal["asymmetric", "discrete", "continuous"]

__all__: list[str]

class Error(RuntimeError):
    """A library error (a non-OK symba::Status); the message is the C++ one."""

class CategorizationOptions:
    min_axis_angle: float
    axis_vote_angle: float
    swing_tolerance: float
    cluster_eps: float
    min_points: int
    merge_close_clusters: bool
    rescue_min_points: int
    max_cluster_extent: float
    min_cluster_separation: float
    separation_ratio: float
    max_noise_fraction: float
    empty_gap_angle: float
    min_empty_fraction: float
    asymmetric_inlier_angle: float
    translation_gate: float
    prior_snap_angle: float
    read_one_mode_with_prior: bool
    def __init__(self, **kwargs: object) -> None: ...
    def validate(self) -> None: ...

class MixtureOptions:
    use_null_hypothesis: bool
    null_weight: float
    null_sigma_scale: float
    def __init__(self, **kwargs: object) -> None: ...

class BackendOptions:
    method: Literal["symba", "mh", "sh"]
    window_size: int
    window_policy: Literal["marginalize", "condition", "drop"]
    marginalize_min_margin: float
    marginalize_rival_distance: float
    chain_prior: Literal["conditional", "marginal"]
    keep_history: bool
    max_iterations: int
    batch_max_iterations: int
    num_threads: int
    hypothesis_sigma_t: float
    hypothesis_sigma_r: float
    gamma: float
    axis_sigma: float
    merge_modes: bool
    object_loss: Literal["none", "huber", "cauchy"]
    object_loss_scale: float
    detection_errors: Literal["log", "independent"]
    mixture: MixtureOptions
    frontend_sigma_t: float
    frontend_sigma_r: float
    point_sigma_px: float
    point_loss_scale: float
    point_depth_sigma_relative: float
    gate_position: float
    gate_axis: float
    gate_rotation: float
    gate_angle: float
    reanchor_angle: float
    confirm_keyframes: int
    tentative_timeout: int
    track_tolerance: float
    gate_sigmas: float
    estimate_noise: bool
    noise_window: int
    noise_min_samples: int
    noise_update_ratio: float
    claimed_noise_tolerance: float
    motion_noise_tolerance: float
    uncalibrated_sigma_t: float
    uncalibrated_sigma_r: float
    scatter_min_hypotheses: int
    min_support: float
    min_support_views: int
    upgrade_evidence: int
    upgrade_min_fraction: float
    upgrade_confusion_rate: float
    upgrade_odds: float
    max_upgrade_order: int
    upgrade_angle_tolerance: float
    detect_loops: bool
    loop_min_objects: int
    loop_recent_keyframes: int
    loop_drift_factor: float
    loop_sigma_t: float
    loop_sigma_r: float
    categorization: CategorizationOptions
    def __init__(self, **kwargs: object) -> None: ...
    def validate(self) -> None: ...

class ClassPrior:
    symmetry: SymmetryName
    order: int
    axis_o: Float64Array  # (3,), object frame; zero = unknown
    def __init__(self, symmetry: SymmetryName = "asymmetric", order: int = 0,
                 axis_o: Optional[ArrayLike] = None) -> None: ...

class PinholeIntrinsics:
    fx: float
    fy: float
    cx: float
    cy: float
    def __init__(self, fx: float, fy: float, cx: float, cy: float) -> None: ...

class Odometry:
    T_prev_cur: Float64Array  # (7,); set with (7,) or (4, 4)
    sigma_t: float
    sigma_r: float
    def __init__(self, T_prev_cur: ArrayLike, sigma_t: float = 0.01,
                 sigma_r: float = 0.005) -> None: ...

class LoopClosure:
    keyframe: int  # the earlier keyframe's id
    T: Float64Array  # (7,); set with (7,) or (4, 4)
    sigma_t: float
    sigma_r: float
    def __init__(self, keyframe: int, T: ArrayLike, sigma_t: float = 0.05,
                 sigma_r: float = 0.02) -> None: ...

class Detection:
    id: str
    class_name: str
    sigma_t: Optional[float]
    sigma_r: Optional[float]
    score: float
    @property
    def hypotheses(self) -> Float64Array: ...  # (N, 7) T_co
    @property
    def weights(self) -> Float64Array: ...  # (N,)
    def __init__(self, class_name: str, hypotheses: ArrayLike,
                 weights: Optional[ArrayLike] = None, id: str = "",
                 sigma_t: Optional[float] = None,
                 sigma_r: Optional[float] = None,
                 score: float = 1.0) -> None: ...
    def set_hypotheses(self, hypotheses: ArrayLike,
                       weights: Optional[ArrayLike] = None) -> None: ...

class Keyframe:
    id: int
    timestamp: float
    T_wc: Optional[Float64Array]  # (7,); set with (7,), (4, 4) or None
    odometry: Optional[Odometry]
    detections: list[Detection]  # a copy; assign a list to change
    loop_closures: list[LoopClosure]  # a copy; assign a list to change
    @property
    def point_ids(self) -> Int64Array: ...  # (M,)
    @property
    def point_uv(self) -> Float64Array: ...  # (M, 2) pixels
    @property
    def point_depth(self) -> Float64Array: ...  # (M,) m; 0 = no depth
    def __init__(self, id: int, timestamp: float,
                 T_wc: Optional[ArrayLike] = None,
                 odometry: Optional[Odometry] = None,
                 detections: Sequence[Detection] = ...,
                 point_ids: Optional[ArrayLike] = None,
                 point_uv: Optional[ArrayLike] = None,
                 point_depth: Optional[ArrayLike] = None,
                 loop_closures: Sequence[LoopClosure] = ...) -> None: ...
    def set_points(self, point_ids: ArrayLike, point_uv: ArrayLike,
                   point_depth: Optional[ArrayLike] = None) -> None: ...
    @staticmethod
    def from_arrays(id: int, timestamp: float, *,
                    T_wc: Optional[ArrayLike] = None,
                    odometry: Union[Odometry, ArrayLike, None] = None,
                    odometry_sigma_t: Optional[float] = None,
                    odometry_sigma_r: Optional[float] = None,
                    hypotheses: Optional[ArrayLike] = None,  # (H, 7)
                    counts: Optional[ArrayLike] = None,  # (D,) int64
                    weights: Optional[ArrayLike] = None,  # (H,)
                    class_names: Optional[Sequence[str]] = None,  # D
                    detection_ids: Optional[Sequence[str]] = None,  # D
                    scores: Optional[ArrayLike] = None,  # (D,)
                    detection_sigma_t: Optional[ArrayLike] = None,  # (D,)
                    detection_sigma_r: Optional[ArrayLike] = None,  # (D,)
                    point_ids: Optional[ArrayLike] = None,
                    point_uv: Optional[ArrayLike] = None,
                    point_depth: Optional[ArrayLike] = None) -> Keyframe: ...

class Trajectory:
    @property
    def ids(self) -> Int64Array: ...  # (N,)
    @property
    def timestamps(self) -> Float64Array: ...  # (N,)
    @property
    def poses(self) -> Float64Array: ...  # (N, 7) T_wc
    def __len__(self) -> int: ...

class MapObject:
    @property
    def id(self) -> int: ...
    @property
    def class_name(self) -> str: ...
    @property
    def symmetry(self) -> SymmetryName: ...
    @property
    def t_wo(self) -> Float64Array: ...  # (3,)
    @property
    def axis_w(self) -> Float64Array: ...  # (3,), zero if asymmetric
    @property
    def axis_o(self) -> Float64Array: ...  # (3,), zero if asymmetric
    @property
    def angles(self) -> Float64Array: ...  # (K,) rad, discrete only
    @property
    def angle_evidence(self) -> Float64Array: ...  # (K,) discrete only
    @property
    def angle_probabilities(self) -> Float64Array: ...  # (K,) sum 1, discrete
    @property
    def poses(self) -> Float64Array: ...  # (K, 7) T_wo
    @property
    def observations(self) -> int: ...
    @property
    def upgrade(self) -> Optional[dict[str, Union[int, float]]]: ...
    @property
    def covariance(self) -> Optional[ObjectCovariance]: ...

# Backend.object_covariances(): position (3, 3) m^2; rotation (3, 3) rad^2
# (asymmetric) or None; axis (3, 3) (symmetric) or None; angle_variances
# rad^2 per discrete angle (None where unknown); source "keyframe_graph",
# "solve" or "prior".
ObjectCovariance = dict[str, Any]

# Backend.keyframe_covariances(ids): id; covariance (6, 6), [t_wc m; world
# rotation vector rad], zero for the first keyframe.
KeyframeCovariance = dict[str, Any]

class Assignment:
    @property
    def keyframe(self) -> int: ...
    @property
    def detection(self) -> str: ...
    @property
    def object(self) -> int: ...  # -1: in no map object
    @property
    def symmetry(self) -> SymmetryName: ...

class SolveReport:
    @property
    def iterations(self) -> int: ...
    @property
    def initial_cost(self) -> float: ...
    @property
    def final_cost(self) -> float: ...
    @property
    def seconds(self) -> float: ...
    @property
    def converged(self) -> bool: ...
    @property
    def free_keyframes(self) -> int: ...
    @property
    def residual_blocks(self) -> int: ...
    @property
    def parameter_blocks(self) -> int: ...
    @property
    def prior_size(self) -> int: ...

class RelocalizationReport:
    @property
    def state(self) -> Literal["searching", "relocalized", "gave up"]: ...
    @property
    def keyframes(self) -> int: ...
    @property
    def attempts(self) -> int: ...
    @property
    def last_outcome(self) -> str: ...
    @property
    def keyframe(self) -> Optional[int]: ...
    @property
    def T_map_run(self) -> Float64Array: ...  # (7,) [tx ty tz qx qy qz qw]
    @property
    def correspondences(self) -> list[tuple[int, int]]: ...
    @property
    def position_rmse(self) -> float: ...
    @property
    def seconds(self) -> float: ...

class BackendStatistics:
    @property
    def keyframes(self) -> int: ...
    @property
    def detections(self) -> int: ...
    @property
    def objects(self) -> int: ...
    @property
    def points(self) -> int: ...
    @property
    def object_upgrades(self) -> int: ...
    @property
    def objects_turned(self) -> int: ...
    @property
    def objects_dropped(self) -> int: ...
    @property
    def rotation_outliers(self) -> int: ...
    @property
    def folded_angles(self) -> int: ...
    @property
    def marginalized_keyframes(self) -> int: ...
    @property
    def ambiguous_edges_dropped(self) -> int: ...
    @property
    def solves(self) -> int: ...
    @property
    def solve_seconds(self) -> float: ...
    @property
    def solve_iterations(self) -> int: ...
    @property
    def point_observations_behind(self) -> int: ...
    @property
    def loop_closures(self) -> int: ...
    @property
    def loop_closures_moved_past(self) -> int: ...
    @property
    def loop_closure_seconds(self) -> float: ...
    @property
    def object_loop_closures(self) -> int: ...
    @property
    def objects_merged(self) -> int: ...
    @property
    def revisits_moved_past(self) -> int: ...

class LoopObjectPair:
    @property
    def map(self) -> int: ...
    @property
    def duplicate(self) -> int: ...
    @property
    def merged(self) -> bool: ...

class LoopClosureReport:
    @property
    def keyframe(self) -> int: ...
    @property
    def other(self) -> int: ...
    @property
    def moved_past(self) -> bool: ...
    @property
    def correction_m(self) -> float: ...
    @property
    def correction_deg(self) -> float: ...
    @property
    def keyframes_moved(self) -> int: ...
    @property
    def initial_cost(self) -> float: ...
    @property
    def final_cost(self) -> float: ...
    @property
    def seconds(self) -> float: ...
    @property
    def waiting(self) -> bool: ...
    @property
    def message(self) -> str: ...
    @property
    def from_objects(self) -> bool: ...
    @property
    def objects(self) -> list[LoopObjectPair]: ...

class NoiseSamples:
    @property
    def levels(self) -> int: ...
    @property
    def increments(self) -> int: ...
    @property
    def sigma_level(self) -> Optional[float]: ...
    @property
    def sigma_increment(self) -> Optional[float]: ...
    @property
    def correlation(self) -> float: ...
    @property
    def inflation(self) -> float: ...

class HypothesisScatter:
    @property
    def detections(self) -> int: ...
    @property
    def sigma_t(self) -> Optional[float]: ...
    @property
    def sigma_r(self) -> Optional[float]: ...

class NoiseClaims:
    @property
    def translation_samples(self) -> int: ...
    @property
    def rotation_samples(self) -> int: ...
    @property
    def scale_t(self) -> Optional[float]: ...
    @property
    def scale_r(self) -> Optional[float]: ...
    @property
    def factor_t(self) -> float: ...
    @property
    def factor_r(self) -> float: ...

class EdgeWeights:
    @property
    def declared(self) -> int: ...
    @property
    def scatter(self) -> int: ...
    @property
    def unstated(self) -> int: ...
    @property
    def sigma_t(self) -> Optional[float]: ...
    @property
    def sigma_r(self) -> Optional[float]: ...

class ClassNoise:
    @property
    def class_name(self) -> str: ...
    @property
    def sigma_t(self) -> Optional[float]: ...
    @property
    def sigma_r(self) -> Optional[float]: ...
    @property
    def weight_sigma_t(self) -> float: ...
    @property
    def weight_sigma_r(self) -> float: ...
    @property
    def translation(self) -> NoiseSamples: ...
    @property
    def rotation(self) -> NoiseSamples: ...
    @property
    def scatter(self) -> HypothesisScatter: ...
    @property
    def claims(self) -> NoiseClaims: ...
    @property
    def track_ratio(self) -> Optional[float]: ...
    @property
    def weights(self) -> EdgeWeights: ...

class MotionClaimGroup:
    @property
    def stated_sigma_t(self) -> float: ...
    @property
    def stated_sigma_r(self) -> float: ...
    @property
    def pairs(self) -> int: ...
    @property
    def scale(self) -> Optional[float]: ...
    @property
    def factor(self) -> float: ...

class MotionNoise:
    @property
    def odometry_steps(self) -> int: ...
    @property
    def odometry_sigma_t(self) -> Optional[float]: ...
    @property
    def odometry_sigma_r(self) -> Optional[float]: ...
    @property
    def frontend_steps(self) -> int: ...
    @property
    def frontend_sigma_t(self) -> Optional[float]: ...
    @property
    def frontend_sigma_r(self) -> Optional[float]: ...
    @property
    def claims(self) -> list[MotionClaimGroup]: ...

class Backend:
    def __init__(self, options: Optional[BackendOptions] = None,
                 intrinsics: Optional[PinholeIntrinsics] = None,
                 class_priors: dict[str, ClassPrior] = ..., *,
                 keep_journal: bool = True) -> None: ...
    # pickle / copy.deepcopy: the same calls again in a new backend.
    def __getstate__(self) -> tuple[object, ...]: ...
    def __setstate__(self, arg0: tuple[object, ...]) -> None: ...
    def add_keyframe(self, keyframe: Keyframe) -> list[Assignment]: ...
    def add_keyframe_arrays(
            self, id: int, timestamp: float, *,
            T_wc: Optional[ArrayLike] = None,
            odometry: Union[Odometry, ArrayLike, None] = None,
            odometry_sigma_t: Optional[float] = None,
            odometry_sigma_r: Optional[float] = None,
            hypotheses: Optional[ArrayLike] = None,  # (H, 7) or (H, 4, 4)
            counts: Optional[ArrayLike] = None,  # (D,) int64
            weights: Optional[ArrayLike] = None,  # (H,)
            class_names: Optional[Sequence[str]] = None,  # D
            detection_ids: Optional[Sequence[str]] = None,  # D
            scores: Optional[ArrayLike] = None,  # (D,)
            detection_sigma_t: Optional[ArrayLike] = None,  # (D,) 0: none
            detection_sigma_r: Optional[ArrayLike] = None,  # (D,) 0: none
            point_ids: Optional[ArrayLike] = None,  # (M,) int64
            point_uv: Optional[ArrayLike] = None,  # (M, 2)
            point_depth: Optional[ArrayLike] = None,  # (M,) 0: none
    ) -> list[Assignment]: ...
    def optimize_window(self) -> SolveReport: ...
    def optimize_batch(self) -> SolveReport: ...
    def keyframe(self, id: int) -> Optional[Float64Array]: ...  # (7,) T_wc
    def object(self, id: int) -> Optional[MapObject]: ...
    def keyframes(self) -> Trajectory: ...
    def objects(self) -> list[MapObject]: ...
    def object_covariances(self) -> list[ObjectCovariance]: ...
    def keyframe_covariances(
            self, ids: list[int]) -> list[KeyframeCovariance]: ...
    def save_map(self, path: Optional[str] = None) -> str: ...
    def load_map(self, path: Optional[str] = None, *,
                 text: Optional[str] = None,
                 relocalize: bool = False) -> None: ...
    def relocalization(self) -> Optional[RelocalizationReport]: ...
    def add_loop_closure(self, keyframe: int,
                         closure: LoopClosure) -> LoopClosureReport: ...
    def loop_closures(self) -> list[LoopClosureReport]: ...
    def give_up_relocalization(self) -> None: ...
    def assignments(self) -> list[Assignment]: ...
    def statistics(self) -> BackendStatistics: ...
    def noise(self) -> list[ClassNoise]: ...
    def motion_noise(self) -> MotionNoise: ...
    @property
    def options(self) -> BackendOptions: ...

class AngleCluster:
    @property
    def theta(self) -> float: ...
    @property
    def spread(self) -> float: ...
    @property
    def weight(self) -> float: ...
    @property
    def members(self) -> Int64Array: ...

class CategorizationDiagnostics:
    @property
    def passes(self) -> int: ...
    @property
    def axis_support(self) -> float: ...
    @property
    def num_axis_inliers(self) -> int: ...
    @property
    def num_raw_clusters(self) -> int: ...
    @property
    def num_noise(self) -> int: ...
    @property
    def max_cluster_extent(self) -> float: ...
    @property
    def min_cluster_separation(self) -> float: ...
    @property
    def empty_fraction(self) -> float: ...
    @property
    def prior_axis_used(self) -> bool: ...
    @property
    def prior_order_snapped(self) -> bool: ...
    @property
    def prior_type_used(self) -> bool: ...

class Categorization:
    @property
    def type(self) -> SymmetryName: ...
    @property
    def reference(self) -> int: ...
    @property
    def T_co_base(self) -> Float64Array: ...  # (7,)
    @property
    def t_co(self) -> Float64Array: ...  # (3,)
    @property
    def axis_o(self) -> Float64Array: ...  # (3,)
    @property
    def axis_c(self) -> Float64Array: ...  # (3,)
    @property
    def clusters(self) -> list[AngleCluster]: ...
    @property
    def inliers(self) -> Int64Array: ...
    @property
    def twist(self) -> Float64Array: ...  # (N,) rad
    @property
    def diagnostics(self) -> CategorizationDiagnostics: ...

def categorize(hypotheses: ArrayLike, weights: Optional[ArrayLike] = None,
               options: Optional[CategorizationOptions] = None,
               prior: Optional[ClassPrior] = None) -> Categorization: ...

class BopSource:
    scene_id: int
    obj_ids: dict[str, int]
    def __init__(self, scene_id: int = 0,
                 obj_ids: dict[str, int] = ...) -> None: ...

class LogHeader:
    @property
    def version(self) -> int: ...
    camera: Optional[PinholeIntrinsics]
    classes: dict[str, ClassPrior]
    bop: Optional[BopSource]
    def __init__(self, camera: Optional[PinholeIntrinsics] = None,
                 classes: dict[str, ClassPrior] = ...,
                 bop: Optional[BopSource] = None) -> None: ...

class LogReader:
    def __init__(self, path: str) -> None: ...
    @property
    def header(self) -> LogHeader: ...
    @property
    def line(self) -> int: ...
    def __iter__(self) -> Iterator[Keyframe]: ...
    def __next__(self) -> Keyframe: ...
    def __enter__(self) -> LogReader: ...
    def __exit__(self, *args: object) -> bool: ...

class LogWriter:
    def __init__(self, path: str, header: LogHeader) -> None: ...
    def write(self, keyframe: Keyframe) -> None: ...
    def close(self) -> None: ...
    def __enter__(self) -> LogWriter: ...
    def __exit__(self, *args: object) -> bool: ...

def read_log(path: str) -> tuple[LogHeader, list[Keyframe]]: ...
def write_log(path: str, header: LogHeader,
              keyframes: Sequence[Keyframe]) -> None: ...

class ReplayResult:
    @property
    def header(self) -> LogHeader: ...
    @property
    def trajectory(self) -> Trajectory: ...
    @property
    def objects(self) -> list[MapObject]: ...
    @property
    def assignments(self) -> list[Assignment]: ...
    @property
    def statistics(self) -> BackendStatistics: ...
    @property
    def last_solve(self) -> SolveReport: ...
    @property
    def seconds(self) -> float: ...
    @property
    def relocalization(self) -> Optional[RelocalizationReport]: ...
    @property
    def loop_closures(self) -> list[LoopClosureReport]: ...
    @property
    def noise(self) -> list[ClassNoise]: ...
    @property
    def motion(self) -> MotionNoise: ...

def replay(log_path: str, options: Optional[BackendOptions] = None,
           mode: Literal["window", "batch"] = "window",
           final_batch: bool = False, map_in: Optional[str] = None,
           map_out: Optional[str] = None,
           relocalize: bool = False) -> ReplayResult: ...

def import_tum(trajectory: str, objects: Sequence[tuple[str, str]],
               stride: int = 5, odometry_sigma_t: float = 0.005,
               odometry_sigma_r: float = 0.01, first_pose: str = "",
               detection_sigma_t: Optional[float] = None,
               detection_sigma_r: Optional[float] = None,
               classes: dict[str, ClassPrior] = ...
               ) -> tuple[LogHeader, list[Keyframe]]: ...
def import_tum_to_log(log_path: str, trajectory: str,
                      objects: Sequence[tuple[str, str]], stride: int = 5,
                      odometry_sigma_t: float = 0.005,
                      odometry_sigma_r: float = 0.01, first_pose: str = "",
                      detection_sigma_t: Optional[float] = None,
                      detection_sigma_r: Optional[float] = None,
                      classes: dict[str, ClassPrior] = ...
                      ) -> tuple[int, int]: ...
class BopImportReport:
    @property
    def rows(self) -> int: ...
    @property
    def keyframes(self) -> int: ...
    @property
    def detections(self) -> int: ...
    @property
    def skipped_images(self) -> int: ...
    @property
    def skipped_rows(self) -> int: ...
    @property
    def other_scene_rows(self) -> int: ...
    @property
    def symmetry_notes(self) -> list[str]: ...

def import_bop(results: str, scene_camera: str, models_info: str = "",
               trajectory: str = "", image_times: str = "",
               scene: Optional[int] = None,
               class_names: dict[int, str] = ...,
               gate: Optional[float] = None,
               skip_images_without_pose: bool = False,
               time_tolerance: float = 0.02,
               detection_sigma_t: Optional[float] = None,
               detection_sigma_r: Optional[float] = None
               ) -> tuple[LogHeader, list[Keyframe], BopImportReport]: ...
def import_bop_to_log(log_path: str, results: str, scene_camera: str,
                      models_info: str = "", trajectory: str = "",
                      image_times: str = "", scene: Optional[int] = None,
                      class_names: dict[int, str] = ...,
                      gate: Optional[float] = None,
                      skip_images_without_pose: bool = False,
                      time_tolerance: float = 0.02,
                      detection_sigma_t: Optional[float] = None,
                      detection_sigma_r: Optional[float] = None
                      ) -> BopImportReport: ...
def parse_class_prior(spec: str) -> tuple[str, ClassPrior]: ...

class SimulatedObject:
    @property
    def class_name(self) -> str: ...
    @property
    def symmetry(self) -> SymmetryName: ...
    @property
    def order(self) -> int: ...
    @property
    def axis_o(self) -> Float64Array: ...  # (3,)
    @property
    def T_wo(self) -> Float64Array: ...  # (7,)

class Simulation:
    @property
    def scene(self) -> str: ...
    @property
    def seed(self) -> int: ...
    @property
    def header(self) -> LogHeader: ...
    @property
    def keyframes(self) -> list[Keyframe]: ...
    @property
    def objects(self) -> list[SimulatedObject]: ...
    @property
    def true_poses(self) -> Float64Array: ...  # (N, 7) T_wc

def scene_names() -> list[str]: ...
def simulate(scene: str, seed: int = 1,
             num_keyframes: Optional[int] = None) -> Simulation: ...

def pose_matrices(poses: ArrayLike) -> Float64Array: ...
def pose_vectors(matrices: ArrayLike) -> Float64Array: ...
