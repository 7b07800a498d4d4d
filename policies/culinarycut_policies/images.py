"""Image preprocessing as each upstream model saw it in training, without TensorFlow: squash resizes with
an antialiased Lanczos-3 (the filter tf.image.resize(method="lanczos3", antialias=True) uses; PIL's
rounding differs, so pixels may differ by a level or so: not tested against TF), TF's
crop_and_resize for OpenVLA's and Octo's 0.9-area centre crops, the JPEG round trip of OpenVLA's
evaluation, openpi's resize-with-pad and RDT's pad-to-square.
Every function takes and returns HxWx3 uint8."""
from __future__ import annotations

import io

import numpy as np
from PIL import Image


def check_rgb(image: np.ndarray, what: str) -> np.ndarray:
    image = np.asarray(image)
    if image.ndim != 3 or image.shape[2] != 3 or image.dtype != np.uint8:
        raise ValueError(f"{what}: expected an HxWx3 uint8 image, got {image.shape} {image.dtype}")
    return image


# OpenVLA's and OpenVLA-OFT's evaluation (resize_image, resize_image_for_policy) JPEG-encode the frame
# first, "as done in RLDS dataset builder" (tf.image.encode_jpeg: quality 95, 4:2:0 chroma), and decode it.
def jpeg_roundtrip(image: np.ndarray, quality: int = 95) -> np.ndarray:
    buffer = io.BytesIO()
    Image.fromarray(check_rgb(image, "image")).save(buffer, format="JPEG", quality=quality, subsampling="4:2:0")
    return np.asarray(Image.open(buffer).convert("RGB"))


# OpenVLA (experiments/robot/libero/libero_utils.py, resize_image) and Octo (ResizeImageWrapper):
# a squash to the model's size, no letterbox. PIL's LANCZOS is an antialiased Lanczos-3 filter like TF's
# lanczos3, not bit-exact with it (the tests check the geometry, not TF's output).
def squash_resize(image: np.ndarray, height: int, width: int) -> np.ndarray:
    image = check_rgb(image, "image")
    if image.shape[:2] == (height, width):
        return image
    return np.asarray(Image.fromarray(image).resize((width, height), resample=Image.LANCZOS))


# OpenVLA's crop_and_resize (experiments/robot/openvla_utils.py): a centre box of `area_fraction` of the
# image (sides scaled by sqrt), sampled bilinearly back to (height, width) in float [0, 1] and converted
# back as TF does.
def center_crop_resize(image: np.ndarray, area_fraction: float, height: int, width: int) -> np.ndarray:
    image = check_rgb(image, "image")
    sampled = _crop_and_resize(image.astype(np.float32) / 255.0, area_fraction, height, width)
    # tf.image.convert_image_dtype(float -> uint8, saturate=True): scale by 255.5 and truncate.
    return (np.clip(sampled, 0.0, 1.0) * 255.5).astype(np.uint8)


# Octo's ResizeImageWrapper (octo/utils/gym_wrappers.py) on its augmented keys (image_primary): the
# average of training's random_resized_crop, a centre box of avg_scale 0.9 of the area, crop_and_resize on
# the 0-255 float image back to its size, then tf.round (half to even) and clipped to uint8.
def octo_center_crop(image: np.ndarray, area_fraction: float = 0.9) -> np.ndarray:
    image = check_rgb(image, "image")
    sampled = _crop_and_resize(image.astype(np.float32), area_fraction, *image.shape[:2])
    return np.clip(np.round(sampled), 0, 255).astype(np.uint8)


def _crop_and_resize(source: np.ndarray, area_fraction: float, height: int, width: int) -> np.ndarray:
    """tf.image.crop_and_resize with the centre box of `area_fraction`: TF's sample positions
    y = y1 (H - 1) + i (y2 - y1) (H - 1) / (h - 1), bilinear."""
    if not 0.0 < area_fraction <= 1.0:
        raise ValueError(f"crop area fraction must be in (0, 1], got {area_fraction}")
    side = float(np.sqrt(np.float32(area_fraction)))
    offset = (1.0 - side) / 2.0
    in_h, in_w = source.shape[:2]
    ys = _sample_positions(offset, offset + side, in_h, height)
    xs = _sample_positions(offset, offset + side, in_w, width)
    return _bilinear(source, ys, xs)


def _sample_positions(start: float, end: float, size_in: int, size_out: int) -> np.ndarray:
    if size_out == 1:
        return np.array([0.5 * (start + end) * (size_in - 1)], dtype=np.float64)
    return start * (size_in - 1) + np.arange(size_out) * (end - start) * (size_in - 1) / (size_out - 1)


def _bilinear(source: np.ndarray, ys: np.ndarray, xs: np.ndarray) -> np.ndarray:
    """TF's CropAndResize arithmetic: top = tl + (tr - tl) x_lerp, bottom likewise, top + (bottom - top)
    y_lerp; the x pass is done once per source row, then rows are picked (the same operations)."""
    y0 = np.floor(ys).astype(int)
    x0 = np.floor(xs).astype(int)
    y1 = np.minimum(y0 + 1, source.shape[0] - 1)
    x1 = np.minimum(x0 + 1, source.shape[1] - 1)
    x_lerp = (xs - x0).astype(np.float32)[None, :, None]
    y_lerp = (ys - y0).astype(np.float32)[:, None, None]
    left = source[:, x0]
    across = left + (source[:, x1] - left) * x_lerp
    top = across[y0]
    return top + (across[y1] - top) * y_lerp


# openpi-client's image_tools.resize_with_pad: keep the aspect ratio, bilinear, pad with zeros, centred.
def resize_with_pad(image: np.ndarray, height: int, width: int) -> np.ndarray:
    image = check_rgb(image, "image")
    in_h, in_w = image.shape[:2]
    if (in_h, in_w) == (height, width):
        return image
    ratio = max(in_w / width, in_h / height)
    new_h, new_w = int(in_h / ratio), int(in_w / ratio)
    resized = Image.fromarray(image).resize((new_w, new_h), resample=Image.BILINEAR)
    canvas = Image.new("RGB", (width, height), 0)
    canvas.paste(resized, (max(0, int((width - new_w) / 2)), max(0, int((height - new_h) / 2))))
    return np.asarray(canvas)


# RDT's expand2square (scripts/agilex_model.py, step): pad the short side with the vision encoder's mean
# colour (SigLIP: 0.5 -> 127), the image centred; then SigLIP's own bicubic resize to `size`.
def pad_square_resize(image: np.ndarray, size: int, background: tuple[int, int, int] = (127, 127, 127)) -> np.ndarray:
    image = check_rgb(image, "image")
    pil = Image.fromarray(image)
    width, height = pil.size
    if width != height:
        side = max(width, height)
        square = Image.new("RGB", (side, side), background)
        square.paste(pil, ((side - width) // 2, (side - height) // 2))
        pil = square
    if pil.size != (size, size):
        pil = pil.resize((size, size), resample=Image.BICUBIC)
    return np.asarray(pil)


def camera_rgb(observation: dict, camera: str) -> np.ndarray:
    """The RGB image of `camera` in a CulinaryCutEnv observation; a clear error when the scene lacks it."""
    sensors = observation.get("sensor_data", {})
    if camera not in sensors or "rgb" not in sensors[camera]:
        raise KeyError(f"the observation has no RGB image from camera {camera!r} (cameras: "
                       f"{', '.join(sorted(sensors)) or 'none'}); the policy's `cameras` should have added it")
    return sensors[camera]["rgb"]
