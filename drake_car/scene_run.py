"""Runs a scene: the settling car or a drive, with only the systems the scene calls for."""

import sys

from drake_car.assembly import build_car_diagram
from drake_car.drive import rolling_radius, run_drive
from drake_car.manoeuvre import drive_trajectory, rack_trajectory
from drake_car.scene import Scene, resolve
from drake_car.settle import run_settle

REPLAY_FRAMES_PER_SECOND = 32.0


def run_scene(scene: Scene, *, meshcat=None, progress=None):
    """Simulates the scene; returns a DriveRun (drives) or a SettleResult (settle). With
    visualization "meshcat_html" the result's ``html`` is the replay page (the caller saves it
    with its other results); with "meshcat_live" the run is shown as it goes."""
    built = resolve(scene)
    mode = scene.visualization.mode
    if mode != "none" and meshcat is None:
        from drake_car.pictures import start_meshcat
        meshcat = start_meshcat()
        print(f"Meshcat: {meshcat.web_url()}", file=sys.stderr)
    elif mode == "none":
        meshcat = None
    rate = scene.visualization.realtime_rate if mode == "meshcat_live" else 0.0
    if mode == "meshcat_html":
        meshcat.StartRecording(frames_per_second=REPLAY_FRAMES_PER_SECOND)
    if scene.manoeuvre.kind == "settle":
        result = run_settle(built.params, friction=built.friction, tyres=built.tyres,
                            road_height=built.road_height,
                            duration_s=built.end_time_s or built.timeline.settle_s,
                            time_step_s=built.time_step_s,
                            record_period_s=built.record_period_s, meshcat=meshcat,
                            realtime_rate=rate, sap_pacer=built.sap_pacer)
    else:
        initial = None
        if built.start == "static_equilibrium":
            from drake_car.study import static_equilibrium
            initial = static_equilibrium(built.params).positions
        result = run_drive(built.case, built.params, friction=built.friction,
                           tyres=built.tyres, timeline=built.timeline,
                           time_step_s=built.time_step_s,
                           record_period_s=built.record_period_s, end_time_s=built.end_time_s,
                           road_height=built.road_height, meshcat=meshcat, progress=progress,
                           channels=built.log_channels, realtime_rate=rate,
                           sap_pacer=built.sap_pacer, initial_positions=initial)
    if mode == "meshcat_html":
        meshcat.StopRecording()
        meshcat.PublishRecording()
        result.html = meshcat.StaticHtml()
    return result


def scene_diagram(scene: Scene, meshcat=None):
    """The scene's Diagram, built as its simulation builds it (for pictures and checks)."""
    built = resolve(scene)
    drive = scene.manoeuvre.kind != "settle"
    if scene.visualization.mode != "none" and meshcat is None:
        from drake_car.pictures import start_meshcat
        meshcat = start_meshcat()
    return build_car_diagram(
        built.params, time_step_s=built.time_step_s, friction=built.friction,
        tyres=built.tyres, road_height=built.road_height, meshcat=meshcat,
        rack_trajectory=(rack_trajectory(built.timeline, _profile(), built.case)
                         if drive else None),
        drive_trajectory=(drive_trajectory(built.timeline, rolling_radius(built.params))
                          if drive else None),
        log_channels=built.log_channels if drive else (), log_period_s=built.record_period_s,
        sap_pacer=built.sap_pacer)


def _profile():
    from drake_car.calibration import calibrated_profile
    return calibrated_profile()


def system_names(scene: Scene):
    return sorted(s.get_name() for s in scene_diagram(scene).diagram.GetSystems())
