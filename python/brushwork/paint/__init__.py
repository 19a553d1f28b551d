"""`brushwork paint`: painting with the simulated brush from a pen in the browser, and replaying
what was painted (`painting` holds the brush, paper and motion log; `server` the web app;
`replay` renders a log without a browser)."""
