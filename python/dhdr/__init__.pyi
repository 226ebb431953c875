# Type stubs of the dhdr module (python/src/py_*.cpp and __init__.py); test_api.py holds every
# public name of the module to an entry here and each entry to a name of the module.
import os
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

__version__: str

ArrayLike = npt.ArrayLike
ImageLike = Union["Image", ArrayLike]
# None (everything), (xbegin, xend, ybegin, yend[, chbegin, chend]) or an OpenImageIO.ROI.
Roi = Optional[Union[Tuple[int, ...], Any]]
LightsLike = Union[str, os.PathLike, Dict[str, Any], Sequence[Union[str, os.PathLike, Dict[str, Any]]]]

class Image:
    """float32 pixels (height, width, channels) in a numpy array, with channel names, an
    origin and metadata."""
    pixels: Optional[npt.NDArray[np.float32]]
    channels: List[str]
    origin: Tuple[int, int]
    @overload
    def __init__(self) -> None: ...
    @overload
    def __init__(self, pixels: ArrayLike, channels: List[str] = ...) -> None: ...
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def nchannels(self) -> int: ...
    @property
    def empty(self) -> bool: ...
    @property
    def attributes(self) -> Dict[str, Any]: ...
    def set_attribute(self, name: str, value: Any) -> None: ...
    def channel(self, name: str) -> npt.NDArray[np.float32]: ...
    def __getitem__(self, name: str) -> npt.NDArray[np.float32]: ...
    def copy(self) -> Image: ...
    def __array__(self, dtype: Any = ...) -> np.ndarray: ...
    def geterror(self) -> str: ...
    def has_error(self) -> bool: ...

class LuminanceStats:
    log_average: float
    max_luminance: float
    min_luminance: float
    pixels: int
    negative_pixels: int
    non_finite_pixels: int
    transparent_pixels: int
    def __init__(self, *, log_average: float, max_luminance: float = 0.0,
                 min_luminance: float = 0.0, pixels: int = 0) -> None: ...

# Reading and writing (py_image_io.cpp, py_lighting.cpp)
def read(path: str, *, layer: str = "", keep_others: bool = True, nthreads: int = 0) -> Image: ...
def layers(path: str) -> List[str]: ...
def write(path: str, image: Union[ImageLike, npt.NDArray[np.uint8], npt.NDArray[np.uint16]], *,
          type: str = "", compression: str = "") -> None: ...
def read_gbuffer(path: str, *, nthreads: int = 0) -> Union[Image, "DeepGBuffer"]: ...
def read_channels(path: str, *, part: int = 0) -> Image: ...
def import_gbuffer(passes: ImageLike, channels: str = "blender") -> Image: ...
def read_lights(lights: LightsLike, *, radiometric: bool = False) -> List[Dict[str, Any]]: ...
def from_imagebuf(buf: Any) -> Image: ...
def to_imagebuf(image: Image) -> Any: ...

# Every image operation: op(dst, src, ...) -> bool (False: dst.geterror()) and
# op(src, ...) -> Image (errors raise RuntimeError; bad arguments ValueError or TypeError).
@overload
def tone_map(dst: Image, src: ImageLike, *, op: str = "reinhard", key: float = 0.18,
             exposure: float = 0.0, white: Union[float, str] = "auto",
             metering: str = "log-average", percentiles: Tuple[float, float] = (5.0, 95.0),
             weights: str = "seed", delta: float = 1e-4, skip_transparent: bool = True,
             stats: Optional[LuminanceStats] = None, phi: float = 8.0, epsilon: float = 0.05,
             drago_bias: float = 0.85, roi: Roi = None, nthreads: int = 0) -> bool: ...
@overload
def tone_map(src: ImageLike, *, op: str = "reinhard", key: float = 0.18, exposure: float = 0.0,
             white: Union[float, str] = "auto", metering: str = "log-average",
             percentiles: Tuple[float, float] = (5.0, 95.0), weights: str = "seed",
             delta: float = 1e-4, skip_transparent: bool = True,
             stats: Optional[LuminanceStats] = None, phi: float = 8.0, epsilon: float = 0.05,
             drago_bias: float = 0.85, roi: Roi = None, nthreads: int = 0) -> Image: ...
def meter(src: ImageLike, *, metering: str = "log-average",
          percentiles: Tuple[float, float] = (5.0, 95.0), weights: str = "seed",
          delta: float = 1e-4, skip_transparent: bool = True, roi: Roi = None,
          nthreads: int = 0) -> LuminanceStats: ...
def adapt_luminance(metered: Sequence[float], *, fps: float = 24.0, rate: float = 0.98,
                    speed: float = 30.0) -> List[float]: ...
def adapt(frames: Sequence[ImageLike], *, fps: float = 24.0, rate: float = 0.98,
          speed: float = 30.0, metering: str = "log-average",
          percentiles: Tuple[float, float] = (5.0, 95.0), weights: str = "seed",
          delta: float = 1e-4, skip_transparent: bool = True,
          nthreads: int = 0) -> List[LuminanceStats]: ...
@overload
def bloom(dst: Image, src: ImageLike, *, threshold: float = 0.8, key: float = 0.18,
          sigma: float = 2.0, strength: float = 1.3, weights: str = "seed", delta: float = 1e-4,
          skip_transparent: bool = True, roi: Roi = None, nthreads: int = 0) -> bool: ...
@overload
def bloom(src: ImageLike, *, threshold: float = 0.8, key: float = 0.18, sigma: float = 2.0,
          strength: float = 1.3, weights: str = "seed", delta: float = 1e-4,
          skip_transparent: bool = True, roi: Roi = None, nthreads: int = 0) -> Image: ...
def bloom_layer(src: ImageLike, *, threshold: float = 0.8, key: float = 0.18, sigma: float = 2.0,
                strength: float = 1.3, weights: str = "seed", delta: float = 1e-4,
                skip_transparent: bool = True, nthreads: int = 0) -> Image: ...
@overload
def edge_aa(dst: Image, src: ImageLike, *, normal: Optional[ImageLike] = None,
            depth: Optional[ImageLike] = None, gbuffer: Optional[ImageLike] = None,
            use: str = "both", normal_weight: float = 1.0, depth_weight: float = 1.0,
            max_offset: float = 0.5, roi: Roi = None, nthreads: int = 0) -> bool: ...
@overload
def edge_aa(src: ImageLike, *, normal: Optional[ImageLike] = None,
            depth: Optional[ImageLike] = None, gbuffer: Optional[ImageLike] = None,
            use: str = "both", normal_weight: float = 1.0, depth_weight: float = 1.0,
            max_offset: float = 0.5, roi: Roi = None, nthreads: int = 0) -> Image: ...
@overload
def motion_blur(dst: Image, src: ImageLike, *, motion: Optional[ImageLike] = None,
                depth: Optional[ImageLike] = None, gbuffer: Optional[ImageLike] = None,
                shutter: float = 0.5, samples: int = 15, max_blur: int = 32,
                depth_softness: float = 0.01, roi: Roi = None, nthreads: int = 0) -> bool: ...
@overload
def motion_blur(src: ImageLike, *, motion: Optional[ImageLike] = None,
                depth: Optional[ImageLike] = None, gbuffer: Optional[ImageLike] = None,
                shutter: float = 0.5, samples: int = 15, max_blur: int = 32,
                depth_softness: float = 0.01, roi: Roi = None, nthreads: int = 0) -> Image: ...
@overload
def to_display(dst: Image, src: ImageLike, *, config: str = "", colorspace: str = "",
               display: str = "", view: str = "", look: str = "", roi: Roi = None,
               nthreads: int = 0) -> bool: ...
@overload
def to_display(src: ImageLike, *, config: str = "", colorspace: str = "", display: str = "",
               view: str = "", look: str = "", roi: Roi = None, nthreads: int = 0) -> Image: ...
@overload
def to_scene_linear(dst: Image, src: ImageLike, *, config: str = "", colorspace: str = "",
                    display: str = "", view: str = "", look: str = "", roi: Roi = None,
                    nthreads: int = 0) -> bool: ...
@overload
def to_scene_linear(src: ImageLike, *, config: str = "", colorspace: str = "",
                    display: str = "", view: str = "", look: str = "", roi: Roi = None,
                    nthreads: int = 0) -> Image: ...
def describe_display(*, config: str = "", colorspace: str = "", display: str = "",
                     view: str = "", look: str = "") -> Tuple[str, str]: ...
@overload
def quantize(dst: Union[npt.NDArray[np.uint8], npt.NDArray[np.uint16]], src: ImageLike, *,
             dither: bool = True, roi: Roi = None, nthreads: int = 0) -> bool: ...
@overload
def quantize(src: ImageLike, *, bits: int = 8, dither: bool = True, roi: Roi = None,
             nthreads: int = 0) -> Union[npt.NDArray[np.uint8], npt.NDArray[np.uint16]]: ...
def replace_non_finite(image: Image, *, zero_negative: bool = False, roi: Roi = None,
                       nthreads: int = 0) -> Dict[str, int]: ...
def prepare_frame(src: ImageLike, *, config: str = "", colorspace: str = "",
                  nthreads: int = 0) -> Image: ...
def tonemap_frame(src: ImageLike, *, stats: Optional[LuminanceStats] = None, config: str = "",
                  colorspace: str = "", display: str = "", view: str = "", look: str = "",
                  bits: Optional[int] = None, dither: bool = True, nthreads: int = 0,
                  op: str = "reinhard", key: float = 0.18, exposure: float = 0.0,
                  white: Union[float, str] = "auto", metering: str = "log-average",
                  percentiles: Tuple[float, float] = (5.0, 95.0), weights: str = "seed",
                  delta: float = 1e-4, skip_transparent: bool = True, phi: float = 8.0,
                  epsilon: float = 0.05,
                  drago_bias: float = 0.85) -> Union[Image, np.ndarray]: ...

# Scenes (py_scene.cpp)
class Scene:
    """A glTF 2.0 or OBJ scene loaded as dhdr-gbuffer loads it."""
    def __init__(self, path: str, *, strict: bool = False,
                 ground_plane: Optional[Union[bool, float]] = None) -> None: ...
    @property
    def path(self) -> str: ...
    @property
    def cameras(self) -> List[Dict[str, Any]]: ...
    @property
    def lights(self) -> List[Dict[str, Any]]: ...
    @property
    def objects(self) -> List[str]: ...
    @property
    def materials(self) -> List[Dict[str, Any]]: ...
    @property
    def bounds(self) -> Tuple[Tuple[float, float, float], Tuple[float, float, float]]: ...
    @property
    def warnings(self) -> List[str]: ...
    @property
    def animations(self) -> List[Dict[str, Any]]: ...
    def posed(self, *, time: Optional[float] = None, frame: Optional[int] = None,
              fps: float = 24.0, animation: Optional[Union[str, int]] = None) -> Scene: ...
    def info(self) -> str: ...

def render_gbuffer(scene: Scene, *, camera: str = "", lookat: Optional[Sequence[float]] = None,
                   fov: float = 0.0, size: Tuple[int, int] = (1920, 1080),
                   frame_all: bool = False, deep: Union[bool, str] = False, max_layers: int = 8,
                   texture_filter: str = "anisotropic", pixel_samples: int = 1,
                   pixel_sampling: str = "adaptive", pixel_filter: str = "blackman-harris",
                   filter_width: float = 1.5,
                   time: Optional[float] = None, frame: Optional[int] = None, fps: float = 24.0,
                   animation: Optional[Union[str, int]] = None,
                   nthreads: int = 0) -> Union[Image, DeepGBuffer]: ...
@overload
def write_gbuffer(path: str, gbuffer: Image) -> None: ...
@overload
def write_gbuffer(path: str, gbuffer: DeepGBuffer) -> None: ...

class DeepGBuffer:
    """A deep G-buffer: per-pixel sample counts and the samples, one row a sample and one
    column a channel, as OpenImageIO's DeepData holds them."""
    def __init__(self, counts: ArrayLike, samples: ArrayLike, channels: List[str] = ...,
                 attributes: Optional[Dict[str, Any]] = None) -> None: ...
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def origin(self) -> Tuple[int, int]: ...
    @property
    def channels(self) -> List[str]: ...
    @property
    def attributes(self) -> Dict[str, Any]: ...
    @property
    def total_samples(self) -> int: ...
    @property
    def counts(self) -> npt.NDArray[np.uint32]: ...
    @property
    def offsets(self) -> npt.NDArray[np.uint32]: ...
    @property
    def samples(self) -> npt.NDArray[np.float32]: ...
    def __getitem__(self, name: str) -> npt.NDArray[np.float32]: ...
    def channel(self, name: str) -> npt.NDArray[np.float32]: ...
    def pixel(self, x: int, y: int) -> npt.NDArray[np.float32]: ...

# Lighting (py_lighting.cpp)
@overload
def light(src: Union[ImageLike, DeepGBuffer], lights: Optional[LightsLike] = None, *,
          scene: Optional[Scene] = None,
          emissive_lights: bool = True, shadows: bool = True, env_samples: int = 16,
          specular_samples: int = 8, catcher_bounce: int = 16,
          probes: Union[str, "Probes", None] = "",
          ao: str = "off", ao_distance: float = 1.0, ao_samples: int = 16,
          background: Optional[Union[Sequence[float], str]] = None,
          plate: Optional[Union[ImageLike, str]] = None, brute_force: bool = False,
          tile: int = 16, shadow_samples: int = 16, light_budget: int = 32,
          env_specular: str = "auto",
          diffuse: str = "lambert", radiometric: bool = False, denoise: bool = True,
          aovs: bool = False, gi: str = "direct", spp: int = 16, path_bounces: int = 8,
          roi: Roi = None, nthreads: int = 0) -> Image: ...
@overload
def light(dst: Image, src: Union[ImageLike, DeepGBuffer],
          lights: Optional[LightsLike] = None, *, scene: Optional[Scene] = None,
          emissive_lights: bool = True, shadows: bool = True,
          env_samples: int = 16, specular_samples: int = 8, catcher_bounce: int = 16,
          probes: Union[str, "Probes", None] = "", ao: str = "off", ao_distance: float = 1.0,
          ao_samples: int = 16,
          background: Optional[Union[Sequence[float], str]] = None,
          plate: Optional[Union[ImageLike, str]] = None, brute_force: bool = False,
          tile: int = 16, shadow_samples: int = 16, light_budget: int = 32,
          env_specular: str = "auto",
          diffuse: str = "lambert", radiometric: bool = False, denoise: bool = True,
          aovs: bool = False, gi: str = "direct", spp: int = 16,
          path_bounces: int = 8, roi: Roi = None, nthreads: int = 0) -> bool: ...

def light_samples(src: DeepGBuffer, lights: Optional[LightsLike] = None, *,
                  scene: Optional[Scene] = None, emissive_lights: bool = True,
                  shadows: bool = True, env_samples: int = 16, specular_samples: int = 8,
                  catcher_bounce: int = 16, probes: Union[str, "Probes", None] = "",
                  ao: str = "off", ao_distance: float = 1.0, ao_samples: int = 16,
                  background: Optional[Union[Sequence[float], str]] = None,
                  plate: Optional[Union[ImageLike, str]] = None, brute_force: bool = False,
                  tile: int = 16, shadow_samples: int = 16, light_budget: int = 32,
          env_specular: str = "auto",
                  diffuse: str = "lambert", radiometric: bool = False, denoise: bool = True,
                  aovs: bool = False, gi: str = "direct", spp: int = 16, path_bounces: int = 8,
                  nthreads: int = 0) -> DeepGBuffer: ...

# Bakes (py_bakes.cpp)
def bake_ibl(environment: Union[str, ImageLike], out: str, *, levels: int = 6, base_width: int = 256,
             samples: int = 128, dfg_size: int = 128, dfg_samples: int = 1024,
             sun_threshold: float = 10.0, nthreads: int = 0) -> Dict[str, Any]: ...
@overload
def bake_probes(scene: Scene, out: None = None, lights: Optional[LightsLike] = None, *,
                spacing: float = 0.0, grid: Optional[Tuple[int, int, int]] = None,
                max_probes: int = 512, rays: int = 256, bounces: int = 0,
                shadow_samples: int = 4, emissive_lights: bool = True,
                radiometric: bool = False, diffuse: str = "lambert",
                nthreads: int = 0) -> Probes: ...
@overload
def bake_probes(scene: Scene, out: str, lights: Optional[LightsLike] = None, *,
                spacing: float = 0.0, grid: Optional[Tuple[int, int, int]] = None,
                max_probes: int = 512, rays: int = 256, bounces: int = 0,
                shadow_samples: int = 4, emissive_lights: bool = True,
                radiometric: bool = False, diffuse: str = "lambert",
                nthreads: int = 0) -> Dict[str, Any]: ...
def read_probes(path: str) -> Probes: ...

class Probes:
    """Light probes in memory: light(probes=) takes them as it takes a dhdr-probes file."""
    @property
    def counts(self) -> Tuple[int, int, int]: ...
    @property
    def origin(self) -> Tuple[float, float, float]: ...
    @property
    def spacing(self) -> Tuple[float, float, float]: ...
    @property
    def rays(self) -> int: ...
    @property
    def bounces(self) -> int: ...
    @property
    def positions(self) -> npt.NDArray[np.float32]: ...
    @property
    def info(self) -> Dict[str, Any]: ...
    def write(self, path: str) -> None: ...
