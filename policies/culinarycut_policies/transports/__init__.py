"""The wire protocols the upstream models are served with: OpenVLA's REST + json-numpy, and openpi's
websocket + msgpack-numpy; what they share (timeouts, retries, latency) is in faults.py."""
