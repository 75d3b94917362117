"""The web server: HTTP pages and API, the WebSocket protocol, the real-time simulation."""
