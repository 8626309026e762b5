"""Still captures of the thermal camera, as a user's tool reads them: one 32-bit float temperature
[deg C] per pixel in a TIFF (written by tifffile), geotagged.

The geotag (where the camera was, its attitude, when) is JSON in the TIFF's ImageDescription tag,
so any TIFF reader finds it as text; the capture time is also the baseline DateTime tag. The image
is a single grey plane, uncompressed, row 0 the image's top.
"""
from __future__ import annotations

import dataclasses
import datetime
import io
import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import tifffile

FORMAT = "firefly-radiometric/1"  # what the description's JSON is: readers check it


@dataclass(frozen=True)
class Geotag:
    """Where and when a still was taken: latitude/longitude [deg], altitude AMSL [m], the vehicle's
    attitude and the gimbal's angles relative to it [deg] (sim/thermal_camera.py's pose_from_attitude
    takes the same), and the UTC time in seconds since the Unix epoch."""
    lat_deg: float
    lon_deg: float
    alt_m: float
    roll_deg: float
    pitch_deg: float
    yaw_deg: float
    gimbal_pitch_deg: float
    gimbal_yaw_deg: float
    time_unix_s: float

    def __post_init__(self) -> None:
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise ValueError(f"geotag {f.name} must be a finite number, got {value!r}")


def save_radiometric(path: str | Path | io.BytesIO, image: np.ndarray, geotag: Geotag) -> None:
    """Write `image` (2-D temperatures, deg C) as a float32 TIFF carrying `geotag`, to a file or
    an in-memory buffer."""
    data = np.asarray(image, dtype=np.float32)
    if data.ndim != 2:
        raise ValueError(f"a radiometric still is one 2-D image, got shape {data.shape}")
    description = json.dumps({"format": FORMAT, "units": "degC", **dataclasses.asdict(geotag)})
    taken = datetime.datetime.fromtimestamp(geotag.time_unix_s, tz=datetime.timezone.utc)
    tifffile.imwrite(path, data, photometric="minisblack", description=description, metadata=None,
                     datetime=taken.strftime("%Y:%m:%d %H:%M:%S"), software="firefly thermal camera")


def radiometric_bytes(image: np.ndarray, geotag: Geotag) -> bytes:
    """The TIFF save_radiometric writes, as bytes (what a camera keeps on its card and serves)."""
    buffer = io.BytesIO()
    save_radiometric(buffer, image, geotag)
    return buffer.getvalue()


def load_radiometric(path: str | Path | io.BytesIO) -> tuple[np.ndarray, Geotag]:
    """The image (float32, deg C) and geotag of a still save_radiometric wrote."""
    with tifffile.TiffFile(path) as tif:
        page = tif.pages[0]
        if not isinstance(page, tifffile.TiffPage):  # the first page is always read in full
            raise ValueError(f"{path}: no first TIFF page")
        image = page.asarray()
        text = page.description
    try:
        meta = json.loads(text)
    except json.JSONDecodeError:
        raise ValueError(f"{path}: no radiometric geotag in the TIFF's description") from None
    if not isinstance(meta, dict) or meta.get("format") != FORMAT:
        raise ValueError(f"{path}: the description is not a {FORMAT} geotag")
    names = [f.name for f in dataclasses.fields(Geotag)]
    missing = [n for n in names if n not in meta]
    if missing:
        raise ValueError(f"{path}: geotag lacks {', '.join(missing)}")
    return np.asarray(image, dtype=np.float32), Geotag(**{n: meta[n] for n in names})
