# Sourced by the browser oracles (browser-oracle.sh, tiles-oracle.sh, tiles-pages.sh,
# docs-pages.sh): npm test tools in a scratch folder, and a folder served on 127.0.0.1.
# npm_tools DIR PACKAGE@VERSION...: installs the packages into DIR/node_modules.
npm_tools() {
  local dir=$1
  shift
  (cd "$dir" && { [ -f package.json ] || npm init -y >/dev/null; } && npm install --silent --no-audit --no-fund "$@")
}
# serve DIR: serves DIR over HTTP on 127.0.0.1:$port (a random port, set here) until the script exits.
serve() {
  port=$((20000 + RANDOM % 20000))
  (cd "$1" && exec python3 -m http.server "$port" --bind 127.0.0.1 >/dev/null 2>&1) &
  server=$!
  trap 'kill $server 2>/dev/null' EXIT
  sleep 1
}
