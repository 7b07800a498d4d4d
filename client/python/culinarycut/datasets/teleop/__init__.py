"""Teleoperation and live view in the browser: a session driven in pd_ee_delta_pose (session), the web
app that serves the page and the JSON/JPEG endpoints next to the simulator (app), who may call it (access:
Host, Origin and the launch's token), the request bodies it takes (bodies), and the page (page.html)."""
