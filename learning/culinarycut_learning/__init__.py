"""CulinaryCut's own learned policy: trained from `culinarycut data export`'s robomimic HDF5 and served
behind openpi's websocket protocol in its LIBERO layout (docs/learning.md)."""
__version__ = "0.1.0"
