"""Fault injection: the SIM_* parameters turned into the simulated vehicle's plain settings.

The parameters are the interface (PARAM_SET at run time, a scenario's [faults] table at start,
its [script] "param" steps at a sim time); sim/ only sees numbers: motor thrust shares, the GPS's
switch, satellites and offset in metres, the barometer's drift rate, the wind, the battery's
resting voltage, the RC receiver's failure, a push (SIM_SHOVE_*), the rangefinder's noise, the
optical flow camera (SIM_FLOW_*).
SIM_LINK_* act on the MAVLink link, not on the sim (faults/link.py); SIM_ADSB_*'s aircraft are
flown by the vehicle's ADS-B update (vehicle.py, adsb/sitl_transceiver.py).
"""
from __future__ import annotations

from firefly.sim.wind import NO_LIMIT, SteadyWind, WindProfile

from firefly.sim.geo import ned_from_global
from firefly.sim.optical_flow import SensorSettings
from firefly.sim.precland import Beacon, quantised_e7
from ..motor_outputs import OUTPUT_OF_MOTOR


def world_values(sim_config) -> dict:
    """The SIM_* values that describe the scenario's own world before any fault: its wind and a
    full battery. They are what a ground station reads back until something changes them.

    A scenario's [wind] is its world's: it blows the same at every height (SIM_WIND_T 1), as the
    fire's plume leans with it at the height the search flies. SIM_WIND_SPD set as on ArduPilot
    SITL (PARAM_SET, a scenario's [faults]) blows with SITL's default profile, weaker near the
    ground; [faults] SIM_WIND_T 0 gives a scenario's wind that profile too."""
    wind = sim_config.wind
    values = {"SIM_WIND_SPD": wind.speed_m_s, "SIM_WIND_DIR": wind.from_direction_deg % 360.0,
              "SIM_BATT_VOLTAGE": sim_config.airframe.battery_cells * 4.2}
    if wind.speed_m_s > 0.0:
        values["SIM_WIND_T"] = NO_LIMIT
    return values


class Faults:
    """Applies every SIM_* parameter to `sim` once, then each one again whenever it changes."""

    def __init__(self, sim, params, origin):
        self.sim = sim
        self.params = params
        self.origin = origin  # GeoPoint the GPS glitch's degrees are measured from
        for apply in dict.fromkeys(APPLY.values()):
            apply(self)
        self.sim.wind.set_mean(self._steady_wind(), immediately=True)  # the scenario's wind from the start
        params.on_change(self.changed)

    def changed(self, name: str, value: float) -> None:
        apply = APPLY.get(name)
        if apply is not None:
            apply(self)

    def _motors(self) -> None:
        """As SITL 4.7: SIM_ENGINE_FAIL a mask of motor outputs (bit 0 = output 1, 0 = none)
        whose PWM above its minimum SIM_ENGINE_MUL scales. A motor's speed follows its PWM about
        linearly (thrust goes as the square of the speed), so it keeps MUL of its speed, MUL**2
        of its thrust."""
        mask, mul = int(self.params["SIM_ENGINE_FAIL"]), self.params["SIM_ENGINE_MUL"]
        self.sim.set_motor_thrust_scale(tuple(mul * mul if mask >> (output - 1) & 1 else 1.0
                                              for output in OUTPUT_OF_MOTOR))

    def _gps(self) -> None:
        p, gps = self.params, self.sim.gps
        gps.enabled = bool(p["SIM_GPS1_ENABLE"]) and not p["SIM_GPS_DISABLE"]  # 4.7's name and 4.5's, both act
        gps.satellites = int(p["SIM_GPS1_NUMSATS"])
        o = self.origin
        n, e, d = ned_from_global(o, o.lat_deg + p["SIM_GPS1_GLTCH_X"], o.lon_deg + p["SIM_GPS1_GLTCH_Y"],
                                  o.alt_m + p["SIM_GPS1_GLTCH_Z"])
        gps.glitch_ned = (n, e, d)
        gps.jam(p["SIM_GPS1_JAM"] == 1)

    def _baro(self) -> None:
        self.sim.baro.set_drift(self.params["SIM_BARO_DRIFT"], self.sim.time_s)

    def _steady_wind(self) -> SteadyWind:
        return SteadyWind(self.params["SIM_WIND_SPD"], self.params["SIM_WIND_DIR"])

    def _wind(self) -> None:
        wind, p = self.sim.wind, self.params
        wind.turbulence_m_s = p["SIM_WIND_TURB"]
        wind.change_tc_s = p["SIM_WIND_TC"]
        wind.profile = WindProfile(int(p["SIM_WIND_T"]), p["SIM_WIND_T_ALT"], p["SIM_WIND_T_COEF"])
        wind.set_mean(self._steady_wind())

    def _battery(self) -> None:
        self.sim.set_battery_resting_voltage(self.params["SIM_BATT_VOLTAGE"])

    def _rc(self) -> None:
        self.sim.rc.fail = int(self.params["SIM_RC_FAIL"])

    def _sonar(self) -> None:
        self.sim.sonar.noise_m = max(0.0, self.params["SIM_SONAR_RND"])

    def _flow(self) -> None:
        p = self.params
        self.sim.flow_camera.settings = SensorSettings(
            bool(p["SIM_FLOW_ENABLE"]), p["SIM_FLOW_RATE"], int(p["SIM_FLOW_DELAY"]), max(0.0, p["SIM_FLOW_RND"]),
            (p["SIM_FLOW_POS_X"], p["SIM_FLOW_POS_Y"], p["SIM_FLOW_POS_Z"]))

    def _precland_beacon(self) -> None:
        """SIM_PLD_*: SITL's beacon, placed as SITL places it (float32 degrees); off, the sim keeps
        the one it had but reports nothing (SITL stops updating it: its last health stands)."""
        p = self.params
        self.sim.beacon_on = bool(p["SIM_PLD_ENABLE"])
        if not p["SIM_PLD_ENABLE"]:
            return
        lat_e7, lon_e7 = quantised_e7(p["SIM_PLD_LAT"]), quantised_e7(p["SIM_PLD_LON"])
        height = p["SIM_PLD_HEIGHT"]
        if lat_e7 == 0 and lon_e7 == 0 and height == 0:
            self.sim.beacon = None
            return
        n, e, _ = ned_from_global(self.origin, lat_e7 * 1e-7, lon_e7 * 1e-7, self.origin.alt_m)
        self.sim.beacon = Beacon(n, e, -height, p["SIM_PLD_ALT_LMT"], p["SIM_PLD_DIST_LMT"], int(p["SIM_PLD_TYPE"]))

    def _shove(self) -> None:
        """SIM_SHOVE_TIME [ms] set: push with SIM_SHOVE_X/Y/Z [m/s^2, body frame] that long. As
        ArduPilot SITL's, the time goes back to 0 (here at once; the push goes on)."""
        p = self.params
        millis = p["SIM_SHOVE_TIME"]
        if millis > 0:
            self.sim.shove((p["SIM_SHOVE_X"], p["SIM_SHOVE_Y"], p["SIM_SHOVE_Z"]), millis / 1000.0)
            p.report("SIM_SHOVE_TIME", 0.0)


APPLY = {
    "SIM_ENGINE_FAIL": Faults._motors, "SIM_ENGINE_MUL": Faults._motors,
    "SIM_GPS_DISABLE": Faults._gps, "SIM_GPS1_ENABLE": Faults._gps, "SIM_GPS1_NUMSATS": Faults._gps, "SIM_GPS1_GLTCH_X": Faults._gps,
    "SIM_GPS1_GLTCH_Y": Faults._gps, "SIM_GPS1_GLTCH_Z": Faults._gps, "SIM_GPS1_JAM": Faults._gps,
    "SIM_BARO_DRIFT": Faults._baro,
    "SIM_WIND_SPD": Faults._wind, "SIM_WIND_DIR": Faults._wind, "SIM_WIND_TURB": Faults._wind,
    "SIM_WIND_TC": Faults._wind, "SIM_WIND_T": Faults._wind, "SIM_WIND_T_ALT": Faults._wind,
    "SIM_WIND_T_COEF": Faults._wind,
    "SIM_BATT_VOLTAGE": Faults._battery,
    "SIM_RC_FAIL": Faults._rc,
    "SIM_SHOVE_TIME": Faults._shove,
    "SIM_SONAR_RND": Faults._sonar,
    **{f"SIM_FLOW_{name}": Faults._flow for name in ("ENABLE", "RATE", "DELAY", "RND", "POS_X", "POS_Y", "POS_Z")},
    **{f"SIM_PLD_{name}": Faults._precland_beacon
       for name in ("ENABLE", "LAT", "LON", "HEIGHT", "ALT_LMT", "DIST_LMT", "TYPE")},
}
