"""Failure videos in the HTML report as small linked thumbnails: the page embeds a JPEG of each video's last
frame (where the failure shows) and links the video file beside the page, so a run with hundreds of failed
tasks makes a page of a few MB instead of hundreds."""
from __future__ import annotations

import io

THUMBNAIL_QUALITY = 80  # JPEG quality: a 160 x 120 frame in about 5 kB


def last_frame_jpeg(gif: bytes) -> bytes:
    """The animation's last frame as a JPEG."""
    from PIL import Image  # Debian's python3-pil (a dependency of matplotlib)
    with Image.open(io.BytesIO(gif)) as animation:
        animation.seek(getattr(animation, "n_frames", 1) - 1)
        frame = animation.convert("RGB")
    buffer = io.BytesIO()
    frame.save(buffer, format="JPEG", quality=THUMBNAIL_QUALITY)
    return buffer.getvalue()
