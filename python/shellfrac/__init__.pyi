# Type stubs of the shellfrac package (the compiled module _shellfrac plus run()). docs/python.md.
import os
from typing import Any, Dict, List, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str
run_interruptible: bool
"""True when run() can be stopped between steps with Ctrl-C (the run driver offers the hook)."""

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int32]
ShellRef = Union[int, str]

class Error(RuntimeError):
    """Base of the errors shellfrac raises on purpose."""

class SceneError(Error, ValueError):
    """A scene that cannot be read or accepted (the checks and messages of `shellfrac validate`)."""
    json_path: str
    """JSON pointer of the offending value, e.g. '/shells/0/material/nu' ('' for the whole document)."""
    file: str
    """The scene's source: a path, or '<python>'."""
    reason: str
    """What is wrong and what is allowed (the message without file and pointer)."""

class NumericalError(Error, ArithmeticError):
    """A numerical failure while stepping; the simulation stays readable."""
    shell: Optional[str]
    solid: Optional[str]
    particle: Optional[int]
    particle_kind: Optional[str]
    """'control point', 'shear particle', 'quadrature point' or 'solid particle'."""
    step: Optional[int]
    """Steps completed before the failing one."""
    time: Optional[float]

class Scene:
    """A scene as plain data (docs/scene-format.md)."""
    name: Optional[str]
    source: str
    @property
    def shell_names(self) -> List[Optional[str]]: ...
    @staticmethod
    def load(path: str) -> Scene:
        """Reads a scene file; raises SceneError."""
    @staticmethod
    def from_dict(d: Dict[str, Any], source: str = "<python>") -> Scene:
        """A scene from a dict shaped like a scene file; raises SceneError with the JSON pointer."""
    @staticmethod
    def from_json(text: str, source: str = "<python>") -> Scene: ...
    @staticmethod
    def default() -> Scene:
        """The built-in default scene."""
    def to_dict(self) -> Dict[str, Any]:
        """The scene's document: from_dict(d).to_dict() == d."""
    def to_json(self, indent: int = 2) -> str: ...
    def validate(self) -> str:
        """Checks as `shellfrac validate` does; returns its description; raises SceneError."""
    def copy(self) -> Scene: ...
    def __eq__(self, other: object) -> bool: ...

class Simulation:
    """A running scene; arrays are read-only views of the solver's memory, updated by every step."""
    def __init__(self, scene: Scene, threads: int = 0) -> None: ...
    def step(self, dt: Optional[float] = None) -> float:
        """One step (default dt: stable_dt()); returns the dt used."""
    def advance_to(self, t: float) -> int:
        """Steps to time t like `shellfrac run` between frames; returns the steps taken."""
    def stable_dt(self) -> float: ...
    @property
    def time(self) -> float: ...
    @property
    def steps(self) -> int: ...
    @property
    def threads(self) -> int: ...
    @property
    def dx(self) -> float: ...
    @property
    def error(self) -> Optional[str]: ...
    @property
    def shell_names(self) -> List[str]: ...
    @property
    def solid_names(self) -> List[str]: ...
    @property
    def kinetic_energy(self) -> float: ...
    def positions(self, shell: ShellRef = 0) -> FloatArray:
        """Control-point positions x_i, (n, 3), read-only view."""
    def velocities(self, shell: ShellRef = 0) -> FloatArray:
        """Control-point velocities v_i, (n, 3), read-only view."""
    def masses(self, shell: ShellRef = 0) -> FloatArray:
        """Lumped control-point masses m_i, (n,), read-only view."""
    def set_velocities(self, shell: ShellRef, v: npt.ArrayLike) -> None: ...
    def shear_particles(self, shell: ShellRef = 0) -> Dict[str, FloatArray]:
        """x, v, mass, director, volume, stress of the Type III particles (views)."""
    def quadrature_parameters(self, shell: ShellRef = 0) -> FloatArray:
        """(xi_1, xi_2) of the in-plane quadrature points, (n, 2), view."""
    def damage(self, shell: ShellRef = 0) -> Optional[FloatArray]:
        """c per quadrature point and layer, (n, layers), view; None without fracture."""
    def damage_history(self, shell: ShellRef = 0) -> Optional[FloatArray]:
        """c_his per quadrature point and layer, (n, layers), view; None without fracture."""
    def deformation_gradients(self, shell: ShellRef = 0) -> FloatArray:
        """F^KL per quadrature point and layer, (n, layers, 3, 3): a copy."""
    def solid_particles(self, solid: ShellRef = 0) -> Dict[str, FloatArray]:
        """x, v, mass, volume, F of a solid's Type I particles (views)."""
    def metrics(self, mesh: bool = False) -> Dict[str, Any]: ...
    def render_mesh(self, shell: ShellRef = 0) -> Dict[str, Any]:
        """vertices, uvs, faces, face_offsets, face_vertices, labels, triangles, triangle_faces (copies)."""
    def crack_graph(self, shell: ShellRef = 0) -> Optional[Tuple[FloatArray, IntArray]]:
        """(vertices (n, 2), edges (m, 2)) in the parameter plane, copies; None if the shell cannot crack."""

def run(scene: Union[Scene, Dict[str, Any], str, os.PathLike], out: Union[str, os.PathLike] = "out",
        threads: int = 0, log: bool = False) -> Dict[str, Any]:
    """Runs a scene like `shellfrac run`; returns summary.json as a dict."""
