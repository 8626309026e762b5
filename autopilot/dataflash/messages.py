"""The table of log messages: every message Firefly logs, as ArduPilot 4.7 defines it (type id,
name, format characters, columns, units and multipliers, read from ArduCopter's own .BIN), and,
for the flight data, how often it is logged, under which LOG_BITMASK bit, and its builder
(flight_data.py). A new message joins here, in one row.

Rates are ArduCopter's with its default LOG_BITMASK: its 10 Hz logging loop writes ATT, RATE,
POS, CTUN, BAT, RCIN, RCOU and the position controller's PSCN/PSCE/PSCD (these only while a mode
flies the position controller); its 25 Hz loop writes each IMU; each GPS sample (5 Hz) a GPS
record; each barometer logs at 10 Hz; the optical flow sensor's OF at its 10 Hz samples (SIM_FLOW_RATE's
default: Firefly logs it at 10 Hz whatever the rate) while it is healthy.
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from firefly.sim.rigid_body import BodyState

from ..views import StreamedView
from . import flight_data as fd
from .encoding import FMT, LogFormat

# LOG_BITMASK bits (ArduCopter defines.h)
ATTITUDE_FAST, ATTITUDE_MED, GPS, PM, CTUN, NTUN, RCIN, IMU = (1 << b for b in range(8))
CMD, CURRENT, RCOUT, OPTFLOW = 1 << 8, 1 << 9, 1 << 10, 1 << 11
CAMERA = 1 << 15
ALWAYS = 0  # logged whatever the bitmask

UNITS = {  # UNIT records: id -> label
    "-": "", "?": "UNKNOWN", "A": "A", "a": "Ah", "d": "deg", "b": "B", "B": "B/s", "k": "deg/s",
    "D": "deglatitude", "e": "deg/s/s", "E": "rad/s", "G": "Gauss", "h": "degheading", "i": "A.s",
    "J": "W.s", "l": "l", "L": "rad/s/s", "m": "m", "n": "m/s", "o": "m/s/s", "O": "degC", "%": "%",
    "S": "satellites", "s": "s", "t": "N.m", "q": "rpm", "r": "rad", "U": "deglongitude",
    "u": "ppm", "v": "V", "P": "Pa", "w": "Ohm", "W": "Watt", "X": "W.h", "y": "l/s", "Y": "us",
    "z": "Hz", "#": "instance",
}
MULTS = {  # MULT records: id -> multiplier
    "-": 0.0, "?": 1.0, "2": 1e2, "1": 1e1, "0": 1.0, "A": 1e-1, "B": 1e-2, "C": 1e-3, "D": 1e-4,
    "E": 1e-5, "F": 1e-6, "G": 1e-7, "I": 1e-9, "!": 3.6, "/": 3600.0,
}


@dataclass(frozen=True)
class Periodic:
    """A flight data message: logged every `every_s` of sim time while its LOG_BITMASK bit (mask;
    ALWAYS: none) is set and, if `when` is given, while when(vehicle) holds. With `instances`
    n > 1 its second column is the instance number and it is logged n times, with the same values
    (Firefly simulates one IMU and one barometer where ArduCopter SITL logs two)."""
    every_s: float
    mask: int
    build: Callable[[StreamedView, BodyState], tuple]
    when: Callable[[StreamedView], bool] | None = None
    instances: int = 1


@dataclass(frozen=True)
class LogMessage:
    format: LogFormat
    periodic: Periodic | None = None


def _row(type_id, name, fmt, columns, units, mults, periodic=None) -> LogMessage:
    return LogMessage(LogFormat(type_id, name, fmt, columns, units, mults), periodic)


def _position_controlled(v: StreamedView) -> bool:
    return v.controls_position()


def _flow_healthy(v: StreamedView) -> bool:
    return v.optical_flow.healthy(v.time_s)


TEN_HZ, TWENTY_FIVE_HZ, FIVE_HZ = 0.1, 0.04, 0.2

MESSAGES: dict[str, LogMessage] = {m.format.name: m for m in (
    LogMessage(FMT),
    _row(116, "FMTU", "QBNN", "TimeUS,FmtType,UnitIds,MultIds", "s---", "F---"),
    _row(117, "UNIT", "QbZ", "TimeUS,Id,Label", "s--", "F--"),
    _row(118, "MULT", "Qbd", "TimeUS,Id,Mult", "s--", "F--"),
    _row(32, "PARM", "QNff", "TimeUS,Name,Value,Default", "s---", "F---"),
    _row(59, "MSG", "QZ", "TimeUS,Message", "s-", "F-"),
    _row(120, "MODE", "QMBB", "TimeUS,Mode,ModeNum,Rsn", "s---", "F---"),
    _row(181, "EV", "QB", "TimeUS,Id", "s-", "F-"),
    _row(184, "ERR", "QBB", "TimeUS,Subsys,ECode", "s--", "F--"),
    _row(93, "CMD", "QHHHffffLLfB", "TimeUS,CTot,CNum,CId,Prm1,Prm2,Prm3,Prm4,Lat,Lng,Alt,Frame",
         "s-------DUm-", "F-------GG0-"),
    _row(81, "CAM", "QBHIHLLeeeccC", "TimeUS,I,Img,GPSTime,GPSWeek,Lat,Lng,Alt,RelAlt,GPSAlt,R,P,Y",
         "s#---DUmmmddd", "F----GGBBBBBB"),
    _row(72, "ATT", "QffffffB", "TimeUS,DesRoll,Roll,DesPitch,Pitch,DesYaw,Yaw,AEKF", "sddddhh-",
         "F000000-", Periodic(TEN_HZ, ALWAYS, fd.att)),
    _row(75, "RATE", "Qfffffffffffff", "TimeUS,RDes,R,ROut,PDes,P,POut,YDes,Y,YOut,ADes,A,AOut,AOutSlew",
         "skk-kk-kk-oo--", "F?????????BB--", Periodic(TEN_HZ, ATTITUDE_MED, fd.rate)),
    _row(74, "POS", "QLLfff", "TimeUS,Lat,Lng,Alt,RelHomeAlt,RelOriginAlt", "sDUmmm", "FGG000",
         Periodic(TEN_HZ, ALWAYS, fd.pos)),
    _row(94, "GPS", "QBBIHBcLLeffffB", "TimeUS,I,Status,GMS,GWk,NSats,HDop,Lat,Lng,Alt,Spd,GCrs,VZ,Yaw,U",
         "s#-s-S-DUmnhnh-", "F--C-0BGGB000--", Periodic(FIVE_HZ, GPS, fd.gps)),
    _row(64, "BARO", "QBfffcfIffBf", "TimeUS,I,Alt,AltAMSL,Press,Temp,CRt,SMS,Offset,GndTemp,H,CPress",
         "s#mmPOnsmO-P", "F-000B0C?0-0", Periodic(TEN_HZ, IMU, fd.baro, instances=fd.BARO_INSTANCES)),
    _row(163, "IMU", "QBffffffIIfBBHH", "TimeUS,I,GyrX,GyrY,GyrZ,AccX,AccY,AccZ,EG,EA,T,GH,AH,GHz,AHz",
         "s#EEEooo--O--zz", "F-000000-----00", Periodic(TWENTY_FIVE_HZ, IMU, fd.imu, instances=fd.IMU_INSTANCES)),
    _row(88, "BAT", "QBfffffcfBBB", "TimeUS,Inst,Volt,VoltR,Curr,CurrTot,EnrgTot,Temp,Res,RemPct,H,SH",
         "s#vvAaXOw%-%", "F-000C0?0000", Periodic(TEN_HZ, CURRENT, fd.bat)),
    _row(0, "CTUN", "Qffffffefffhh", "TimeUS,ThI,ABst,ThO,ThH,DAlt,Alt,BAlt,DSAlt,SAlt,TAlt,DCRt,CRt",
         "s----mmmmmmnn", "F----00B000BB", Periodic(TEN_HZ, CTUN, fd.ctun)),
    _row(188, "PSCN", "Qfffffffff", "TimeUS,DPN,TPN,PN,DVN,TVN,VN,DAN,TAN,AN", "smmmnnnooo", "F000000000",
         Periodic(TEN_HZ, NTUN, fd.pscn, _position_controlled)),
    _row(189, "PSCE", "Qfffffffff", "TimeUS,DPE,TPE,PE,DVE,TVE,VE,DAE,TAE,AE", "smmmnnnooo", "F000000000",
         Periodic(TEN_HZ, NTUN, fd.psce, _position_controlled)),
    _row(190, "PSCD", "Qfffffffff", "TimeUS,DPD,TPD,PD,DVD,TVD,VD,DAD,TAD,AD", "smmmnnnooo", "F000000000",
         Periodic(TEN_HZ, NTUN, fd.pscd, _position_controlled)),
    _row(60, "RCIN", "QHHHHHHHHHHHHHH", "TimeUS," + ",".join(f"C{i}" for i in range(1, 15)),
         "s" + "Y" * 14, "F" + "-" * 14, Periodic(TEN_HZ, RCIN, fd.rcin)),
    _row(180, "OF", "QBffff", "TimeUS,Qual,flowX,flowY,bodyX,bodyY", "s-EEEE", "F-0000",
         Periodic(TEN_HZ, OPTFLOW, fd.optical_flow, _flow_healthy)),
    _row(62, "RCOU", "QHHHHHHHHHHHHHH", "TimeUS," + ",".join(f"C{i}" for i in range(1, 15)),
         "s" + "Y" * 14, "F" + "-" * 14, Periodic(TEN_HZ, RCOUT, fd.rcou)),
)}
FORMATS = {name: m.format for name, m in MESSAGES.items()}
PERIODIC = tuple((m.format, m.periodic) for m in MESSAGES.values() if m.periodic is not None)


def _check_ids_unique() -> None:
    ids = [m.format.type_id for m in MESSAGES.values()]
    if len(ids) != len(set(ids)):
        raise ValueError("two log messages share a type id")


_check_ids_unique()
