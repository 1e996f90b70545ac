"""Type stubs of the native module (pybind11 over the C++ core). Arrays are numpy; shapes are
given as (bodies, frames, ...) where bodies is the library scene's body count. A test checks that
every public name of the module is declared here."""
from typing import Callable, Dict, List, Optional, Sequence, Tuple, overload

import numpy as np

class SceneError(ValueError): ...
class LibraryError(IOError): ...
class CodecError(ValueError): ...
class RefineError(ValueError): ...
class GoalError(ValueError): ...

class BodyRole:
    """What the simulation does with a body."""
    SIMULATED: "BodyRole"
    ANIMATED: "BodyRole"
    STATIC: "BodyRole"
    DISABLED: "BodyRole"
    name: str
    value: int

def body_role(passive: bool, enabled: bool, animated_throughout: bool) -> BodyRole: ...

class Scene:
    """A rigid-body scene in Blender's units (metres, kg, s, Z up)."""
    name: str
    body_names: List[str]
    body_objects: List[str]  # per body: the object it stands for
    body_roles: List[BodyRole]
    simulated_bodies: List[int]  # indices of the BodyRole.SIMULATED bodies
    constraint_names: List[str]
    frame_start: int
    fps: float
    @staticmethod
    def from_json(text: str) -> "Scene": ...
    @staticmethod
    def load(path: str) -> "Scene": ...
    def to_json(self) -> str: ...

class SimulationParameters:
    duration_s: float
    stop_at_rest: bool
    min_step_hz: float
    record_hz: float
    alpha_linear: float
    alpha_angular: float
    lobe_exponent: float
    impact_linear_factor: float
    impact_angular_factor: float
    rest_linear_speed: float
    rest_angular_speed: float
    rest_duration_s: float
    checkpoint_interval_s: float
    max_speed_mps: float
    max_distance_m: float
    perturb: bool
    sleep: bool
    sleep_linear_speed: float
    sleep_angular_speed: float
    sleep_delay_s: float
    def __init__(self) -> None: ...

class World:
    """One simulated world, uncompressed."""
    world_index: int
    seed: int
    status: str
    reject_reason: str
    record_hz: float
    step_hz: float
    frame_count: int
    body_count: int
    positions: np.ndarray     # float64 (bodies, frames, 3), object origins
    orientations: np.ndarray  # float64 (bodies, frames, 4), (w, x, y, z)
    rest_time_s: np.ndarray   # float64 (bodies,)
    contacts: Dict[str, np.ndarray]
    checkpoints: List[dict]
    impacts_perturbed: int
    simulated_time_s: float
    hash: int

class LineageStep:
    branch_time_s: float
    world: int
    bodies: List[int]
    added: List[int]
    removed: List[int]

class WorldInfo:
    seed: int
    parent_world: int  # -1 for a sampled world
    branch_time_s: float
    record_hz: float
    first_frame: int
    frame_count: int
    simulated_time_s: float
    impacts_perturbed: int
    checkpoint_count: int
    root_world: int
    lineage: List[LineageStep]
    changed_bodies: List[bool]
    motion_bytes: int

class LibraryHeader:
    """The run a library holds, as sampled."""
    scene_json: str          # the scene the worlds were sampled in
    base_seed: int
    position_error_max_m: float
    rotation_error_max_rad: float
    scene_hash: str
    run_hash: str
    engine_build: str        # empty in libraries made before builds were recorded
    parameters: SimulationParameters

class WorldMetrics:
    """A world's stored metrics: per name, one value per scene body (0 for absent bodies)."""
    names: List[str]
    def __getitem__(self, name: str) -> List[float]: ...
    def __contains__(self, name: str) -> bool: ...
    def get(self, name: str, otherwise: Sequence[float] = ()) -> List[float]: ...

class Library:
    """A .mwb library file: run header, worlds (compressed in memory), rejections."""
    path: str
    header: LibraryHeader
    scene_json: str
    body_count: int
    run_last_frame: int
    next_world_index: int
    warnings: List[str]
    file_bytes: int
    world_indices: List[int]
    rejections: List[Tuple[int, int, str]]  # (world index, seed, reason)
    def __init__(self, path: str, polyline_hz: float = 30.0) -> None: ...
    def poll(self) -> int: ...
    def present(self, world: int) -> List[bool]: ...
    def frame_count(self, world: int) -> int: ...
    def positions(self, world: int) -> np.ndarray: ...     # float64 (bodies, frames, 3), NaN if absent
    def orientations(self, world: int) -> np.ndarray: ...  # float64 (bodies, frames, 4), NaN if absent
    def pose(self, world: int, body: int, frame: int) -> Tuple[Sequence[float], Sequence[float]]: ...
    def poses(self, world: int, frames: Sequence[float],
              bodies: Optional[Sequence[int]] = None) -> Tuple[np.ndarray, np.ndarray]: ...
    # (loc (bodies, n, 3), rot (bodies, n, 4)) at fractional recorded frames, as bake and preview pose
    def polyline(self, world: int) -> np.ndarray: ...      # float32 (bodies, points, 3), NaN if absent
    def polylines(self, worlds: Sequence[int], bodies: Sequence[int], stride: int = 1) -> np.ndarray: ...
    # float32 (worlds, bodies, points, 3): polyline(w)[bodies] at every stride-th point and the last;
    # NaN for absent bodies and past a shorter path's end
    def polyline_stride(self, world: int) -> int: ...
    def rest_times(self, world: int) -> List[float]: ...
    def contacts(self, world: int) -> List[Tuple[float, int, int, float]]: ...
    def metrics(self, world: int) -> WorldMetrics: ...
    def world_info(self, world: int) -> WorldInfo: ...

class QueryBox:
    negative: bool
    bodies: List[int]
    swept: bool
    after: int  # position of the part this one must be met after, among the parts queried together; -1: none
    is_pose: bool  # a pose part (pose_part), not a screen box
    def __init__(self, view: np.ndarray, projection: np.ndarray, viewport: Tuple[float, float],
                 rect: Sequence[float], negative: bool = False, bodies: Sequence[int] = ...,
                 time_window: Optional[Tuple[float, float]] = None, swept: bool = False,
                 after: int = -1) -> None: ...

def pose_part(bodies: Sequence[int], within_deg: float, axis: Tuple[float, float, float] = (0, 0, 1),
              target: Tuple[float, float, float] = (0, 0, 1), negative: bool = False, longer_than_s: float = 0.0,
              time_window: Optional[Tuple[float, float]] = None, after: int = -1) -> QueryBox:
    """Each body's own `axis` within `within_deg` of the world direction `target` over the window;
    negative: none held so for longer than longer_than_s. Queried by an index filled with add_library."""

class RankingMetric:
    name: str
    label: str
    unit: str  # 'rad', 's', 'm', 'hits' or 'parts'
    help: str

class QueryResult:
    """What a query of boxes found, over every indexed world."""
    world_indices: np.ndarray     # uint64, every indexed world in world-index order
    boxes_satisfied: np.ndarray   # uint32, per world of world_indices
    matching: np.ndarray          # uint64, the worlds meeting every box
    superseded: bool              # a newer query was posted; the rest is incomplete

class Ranking:
    """Worlds sorted by a metric."""
    world_indices: np.ndarray     # uint64
    values: np.ndarray            # float64, per world of world_indices

class GoalScore:
    """How far a world gets towards a goal."""
    boxes_met: int
    met: List[bool]
    met_time_s: List[float]
    first_unmet: int              # -1: every box is met
    closeness: float              # to the first unmet box, in [0, 1); broken worlds: how late they broke
    violation_time_s: float       # when it first entered a negative part it misses; inf if none
    parts_before_violation: int   # parts met before that moment, poses waiting on a missed box left out (boxes_met when neither)
    value: float                  # parts_before_violation + closeness: what a search ranks by
    failure_time_s: float
    failing_bodies: List[int]

class PathIndex:
    world_count: int
    memory_bytes: int
    def __init__(self, body_radii_m: Sequence[float]) -> None: ...
    def add_library(self, library: Library, threads: int = 0, limit: int = 0) -> int: ...
    def query(self, boxes: Sequence[QueryBox], generation: int = 0, brute_force: bool = False) -> QueryResult: ...
    def post_generation(self, generation: int) -> None: ...
    def rank(self, metric: str, bodies: Sequence[int], combine: str = "sum", descending: bool = False,
             only: Optional[Sequence[int]] = None, goals: Optional[Sequence[Sequence[float]]] = None,
             boxes: Optional[Sequence[QueryBox]] = None) -> Ranking: ...
    def score(self, world: int, boxes: Sequence[QueryBox]) -> GoalScore: ...
    def first_time_inside(self, world: int, bodies: Sequence[int], box: QueryBox) -> float: ...

class RunSettings:
    """The settings of a sampling run a person chooses; unset ones take the product's defaults."""
    seed: int
    duration_s: float        # <= 0: the scene's frame range
    stop_at_rest: bool
    alpha: float
    position_error_m: float
    rotation_error_deg: float
    def __init__(self, seed: int = 0, duration_s: Optional[float] = None, stop_at_rest: Optional[bool] = None,
                 alpha: Optional[float] = None, position_error_m: Optional[float] = None,
                 rotation_error_deg: Optional[float] = None) -> None: ...

class LibraryHolding:
    """What a library file says about a run about to go into it."""
    NEW: "LibraryHolding"
    SAME: "LibraryHolding"
    OTHER: "LibraryHolding"
    name: str
    value: int

class EngineExit:
    """mwb-engine's exit status."""
    OK: "EngineExit"
    FAILED: "EngineExit"
    USAGE: "EngineExit"
    INVALID_SCENE: "EngineExit"
    BAD_LIBRARY: "EngineExit"
    CANCELLED: "EngineExit"
    name: str
    value: int

class engine_protocol:
    """mwb-engine's events (a submodule): the names every reader must know."""
    VERSION: int
    EVENTS: Tuple[str, ...]
    ERROR_CODES: Tuple[str, ...]
    WARNING_CODES: Tuple[str, ...]

def run_hash(scene_json: str, settings: RunSettings) -> str: ...
def run_header(scene_json: str, settings: RunSettings) -> LibraryHeader: ...
@overload
def library_holds_run(library: str, scene_json: str, settings: RunSettings) -> LibraryHolding: ...
@overload
def library_holds_run(library: str, run: LibraryHeader) -> LibraryHolding: ...
def validate_scene_json(text: str) -> List[str]: ...
def sample(scene: Scene, parameters: SimulationParameters, base_seed: int, first_world: int, world_count: int,
           threads: int = 0, on_world: Optional[Callable[[World], None]] = None) -> List[World]: ...
def refine_stored_world(library: str, world: int, bodies: Sequence[int], branch_time_s: float, count: int,
                        threads: int = 0, first_child: int = -1) -> "RefineResult": ...

class RefineResult:
    """What a refinement in this process made."""
    children: List[int]   # the new worlds' indices
    stored: int
    rejected: int
def thinned_indices(points: int, stride: int) -> np.ndarray: ...
def merge_libraries(inputs: Sequence[str], output: str) -> List[str]: ...
def body_bounding_radii(scene: Scene) -> List[float]: ...
def ranking_metrics() -> List[RankingMetric]: ...
def goal_order(afters: Sequence[int]) -> List[int]: ...  # ValueError: a part after itself, a missing part, a cycle
def check_goal(boxes: Sequence[QueryBox]) -> None: ...
def worlds_meeting_goal(library_path: str, goal_json: str, threads: int = 0) -> List[int]: ...
def ode_random_calls_on_this_thread() -> int: ...
