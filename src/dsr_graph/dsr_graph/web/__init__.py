"""The web side (aiohttp, no ROS): the viewer's application and Server-Sent Events; the page,
scripts and styles it serves."""
