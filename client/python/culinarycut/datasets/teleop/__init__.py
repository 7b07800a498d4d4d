"""Teleoperation and live view in the browser: a session driven in pd_ee_delta_pose (session), the web
app that serves the page and the JSON/JPEG endpoints next to the simulator (app), and the page (page.html)."""
