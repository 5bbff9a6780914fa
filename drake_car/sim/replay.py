"""The Meshcat replay of a run: a self-contained HTML page with the car (Drake's
MeshcatVisualizer, recorded), the road with the lane markings of both lanes and any bump, and a
camera that follows the car or frames the whole manoeuvre.

How the camera follows (measured on Drake 1.51's Meshcat): ``SetCameraPose`` is not recorded
into an animation, and Meshcat's orbit controls always look at a fixed world target. So the
"follow" camera stays put behind the car's start and the recorded animation moves the world
(the ``/drake`` path, which holds the car and the road) back by the car's travel: the car stays
in view, and orbit and zoom keep working around it. "overview" frames the whole road from above.
Meshcat's default lights reach about 10 m from the origin, so the replay lights the scene from
above instead.
"""

import math

import numpy as np
from pydrake.geometry import Box, Meshcat, MeshcatParams, Rgba
from pydrake.math import RigidTransform

from drake_car.law.road.profiles import CosineBump, SampledProfile
from drake_car.scene.manoeuvres import LaneChange, speed_profile

LANE_WIDTH_M = 3.7  # the paper's lane change: 3.7 m sideways
CHASE_OFFSET_M = np.array([-11.0, 0.0, 4.5])  # camera relative to the car
LOOK_AHEAD_M = np.array([6.0, 0.0, 0.0])  # where it aims, relative to the car
ROAD_GREY = Rgba(0.5, 0.5, 0.52, 1.0)
WHITE = Rgba(1.0, 1.0, 1.0, 1.0)
BUMP_YELLOW = Rgba(1.0, 0.85, 0.0, 1.0)
CONE_ORANGE = Rgba(1.0, 0.45, 0.1, 1.0)
CONES_PER_LANE_EDGE = 5  # drawn along each edge of a cone lane (the standard's spacing: not at hand)
PATH_MARK_SPACING_M = 2.0  # a path manoeuvre's path drawn as a dotted line


def start_meshcat():
    """A Meshcat server on localhost (any free port)."""
    params = MeshcatParams()
    params.host = "localhost"
    params.port = 0
    return Meshcat(params)


def road_extent(scene):
    """(x_min, x_max) of the road drawn: the car's whole run with margins."""
    timeline = getattr(scene.manoeuvre, "timeline", None)
    travel = 0.0
    if timeline is not None:
        _, s, _ = speed_profile(np.array([scene.end_time_s]), timeline)
        travel = float(s[0])
    return -20.0, travel + 40.0


def lane_markings(scene):
    """(y, dashed) of the markings: the car's lane (centred on y = 0) and the lane it changes
    to (left for case a, right for case b; left otherwise)."""
    sign = -1.0 if isinstance(scene.manoeuvre, LaneChange) and scene.manoeuvre.case == "b" \
        else 1.0
    half = LANE_WIDTH_M / 2
    return [(-sign * half, False), (sign * half, True), (sign * (half + LANE_WIDTH_M), False)]


def _path_marks(scene):
    """(x, y) arrays of a path manoeuvre's path every PATH_MARK_SPACING_M (empty otherwise)."""
    centre_line = getattr(scene.manoeuvre, "centre_line", None)
    if centre_line is None:
        return np.zeros(0), np.zeros(0)
    line = centre_line()
    stations = np.arange(0.0, line.length_m, PATH_MARK_SPACING_M)
    return np.interp(stations, line.station, line.x), np.interp(stations, line.station, line.y)


def _cones(scene):
    """(x, y) of the cones along a cone-lane manoeuvre's lane edges."""
    lanes = getattr(scene.manoeuvre, "lanes", None)
    if lanes is None:
        return []
    return [(x, y) for lane in lanes()
            for x in np.linspace(lane.start_m, lane.end_m, CONES_PER_LANE_EDGE)
            for y in (lane.left_m, lane.right_m)]


class ReplayRecorder:
    """Records a run into a replay page. ``frame(root_context)`` after each advance adds the
    camera's animation; ``finish()`` returns the page."""

    def __init__(self, meshcat, built, visualization):
        self._meshcat = meshcat
        self._built = built
        self._camera = visualization.camera
        self._period = 1.0 / visualization.frames_per_second
        self._next = 0.0
        self._start = None
        scene = built.scene
        meshcat.Delete()
        meshcat.DeleteRecording()
        meshcat.SetProperty("/Grid", "visible", False)  # it would flicker against the road
        meshcat.SetProperty("/Axes", "visible", False)
        _light_from_above(meshcat)
        self._draw_road(scene)
        meshcat.StartRecording(frames_per_second=visualization.frames_per_second,
                               set_visualizations_while_recording=False)

    def _draw_road(self, scene):
        m = self._meshcat
        x_min, x_max = road_extent(scene)
        markings = lane_markings(scene)
        ys = [y for y, _ in markings]
        marks = _path_marks(scene)
        y_min, y_max = min(ys + list(marks[1])) - 1.0, max(ys + list(marks[1])) + 1.0
        length = x_max - x_min
        m.SetObject("/drake/road/asphalt", Box(length, y_max - y_min, 0.1), ROAD_GREY)
        m.SetTransform("/drake/road/asphalt", RigidTransform(
            [0.5 * (x_min + x_max), 0.5 * (y_min + y_max), -0.05 - 0.005]))
        for i, (y, dashed) in enumerate(markings):
            if not dashed:
                path = f"/drake/road/markings/line{i}"
                m.SetObject(path, Box(length, 0.15, 0.01), WHITE)
                m.SetTransform(path, RigidTransform([0.5 * (x_min + x_max), y, 0.0]))
                continue
            for k, x in enumerate(np.arange(x_min, x_max - 3.0, 9.0)):  # 3 m dash, 6 m gap
                path = f"/drake/road/markings/line{i}/dash{k:03d}"
                m.SetObject(path, Box(3.0, 0.15, 0.01), WHITE)
                m.SetTransform(path, RigidTransform([x + 1.5, y, 0.0]))
        for k, (x, y) in enumerate(zip(*marks)):
            m.SetObject(f"/drake/road/path/mark{k:04d}", Box(0.5, 0.15, 0.012), WHITE)
            m.SetTransform(f"/drake/road/path/mark{k:04d}", RigidTransform([x, y, 0.0]))
        for k, (x, y) in enumerate(_cones(scene)):
            m.SetObject(f"/drake/road/cones/cone{k:03d}", Box(0.3, 0.3, 0.5), CONE_ORANGE)
            m.SetTransform(f"/drake/road/cones/cone{k:03d}", RigidTransform([x, y, 0.25]))
        road = scene.road
        if isinstance(road, CosineBump):
            height = abs(road.height_m)
            m.SetObject("/drake/road/bump", Box(road.length_m, y_max - y_min, height),
                        BUMP_YELLOW)
            m.SetTransform("/drake/road/bump", RigidTransform(
                [road.start_x_m + 0.5 * road.length_m, 0.5 * (y_min + y_max),
                 math.copysign(0.5 * height, road.height_m)]))
        elif isinstance(road, SampledProfile):
            # one strip per segment and track (left: y >= 0, right: y < 0)
            tracks = ((("", road.z_m, y_min, y_max),) if not len(road.z_right_m) else
                      (("left", road.z_m, 0.0, y_max), ("right", road.z_right_m, y_min, 0.0)))
            for side, heights, lo, hi in tracks:
                for k in range(len(road.x_m) - 1):
                    x0, x1 = road.x_m[k], road.x_m[k + 1]
                    z = 0.5 * (heights[k] + heights[k + 1])
                    path = f"/drake/road/profile{side}/segment{k:04d}"
                    m.SetObject(path, Box(x1 - x0, hi - lo, 0.02), BUMP_YELLOW)
                    m.SetTransform(path, RigidTransform([0.5 * (x0 + x1), 0.5 * (lo + hi), z]))

    def _car_position(self, root):
        built = self._built
        pc = built.plant.GetMyContextFromRoot(root)
        return built.car.body("chassis").EvalPoseInWorld(pc).translation().copy()

    def frame(self, root):
        t = root.get_time()
        if self._start is None:
            self._start = self._car_position(root)
            self._set_camera(self._start)
        if t + 1e-9 < self._next:
            return
        self._next = t + self._period
        if self._camera != "follow":
            return
        travel = self._car_position(root) - self._start
        travel[2] = 0.0  # the camera does not bounce with the body
        self._meshcat.SetTransform("/drake", RigidTransform(-travel), time_in_recording=t)

    def _set_camera(self, start):
        m = self._meshcat
        if self._camera == "follow":
            m.SetCamera(Meshcat.PerspectiveCamera(fov=60, near=0.1, far=400))
            m.SetCameraPose(start + CHASE_OFFSET_M, start + LOOK_AHEAD_M)
        else:
            x_min, x_max = road_extent(self._built.scene)
            middle = 0.5 * (x_min + x_max)
            span = x_max - x_min
            m.SetCamera(Meshcat.PerspectiveCamera(fov=45, near=0.1, far=4 * span))
            m.SetCameraPose([middle, -0.5 * span, 0.6 * span], [middle, 0.0, 0.0])

    def finish(self):
        m = self._meshcat
        m.StopRecording()
        m.PublishRecording()
        return m.StaticHtml()


def _light_from_above(meshcat):
    meshcat.SetProperty("/Lights/PointLightNegativeX", "visible", False)
    meshcat.SetProperty("/Lights/PointLightPositiveX", "visible", False)
    meshcat.SetProperty("/Lights/AmbientLight/<object>", "intensity", 1.2)
    meshcat.SetProperty("/Lights/FillLight/<object>", "intensity", 2.5)
    meshcat.SetProperty("/Lights/FillLight/<object>", "position", [-4.0, -6.0, 10.0])
