# syntax=docker/dockerfile:1
#
# The `muse` binary plus the committed study and scenario files, for sharded sweeps on
# Kubernetes, on Slurm (via Apptainer/Singularity) or anywhere Docker runs. See deploy/README.md.
#
#   docker build -t muse .
#   docker run --rm muse sweep --help
#   docker run --rm --user "$(id -u):$(id -g)" -v "$PWD/results:/results" \
#       muse sweep --study studies/paper.toml --shard 0/4 --out /results/shard-0
#
# Needs BuildKit (the default builder since Docker 23) for the cache mounts below.

# ---- build ---------------------------------------------------------------------------------
# Same Debian release as the runtime stage, so the binary's glibc requirement is met there.
FROM rust:1.95-slim-bookworm AS builder
WORKDIR /build

# Only what the build reads: the manifests, the sources, and the files the crates embed with
# include_str! (data/ and scenarios/ from muse-scenario; crates/*/web, testdata stay inside
# crates/). Copying these explicitly, not the whole context, means editing a study, the README
# or deploy/ does not recompile anything. There are no build.rs scripts.
COPY Cargo.toml Cargo.lock ./
COPY src/ src/
COPY crates/ crates/
COPY data/ data/
COPY scenarios/ scenarios/

# Dependency caching: the crates.io downloads live in a BuildKit cache mount, reused across
# builds; compilation itself always starts clean (no cached target/, so no stale-mtime risk).
# --locked: build exactly Cargo.lock's versions.
RUN --mount=type=cache,target=/usr/local/cargo/registry \
    --mount=type=cache,target=/usr/local/cargo/git \
    cargo build --release --locked --bin muse \
 && install -D -m 0755 target/release/muse /out/muse

# ---- run -----------------------------------------------------------------------------------
# debian:bookworm-slim rather than gcr.io/distroless/cc-debian12: the binary links only glibc
# (libc, libm, libgcc_s), so both would do, but the slim image has /bin/sh. The merge job
# needs a shell to expand `shard-*` globs, `kubectl cp` needs `tar` in the container, and
# a shell helps when debugging a pod. The cost is ~75 MB more than distroless.
# No network, TLS or CA certificates are needed at run time.
FROM debian:bookworm-slim

# A fixed, non-root uid/gid (10001) so volume permissions can be granted to it (fsGroup on
# Kubernetes, `--user` or chown with Docker).
RUN groupadd --system --gid 10001 muse \
 && useradd --system --uid 10001 --gid muse --home-dir /muse --no-create-home \
        --shell /usr/sbin/nologin muse

COPY --from=builder /out/muse /usr/local/bin/muse

# Studies name their input files relative to the study file, and `muse sweep merge` re-reads
# those inputs from the working directory, so every shard and the merge run in /muse with the
# same files.
WORKDIR /muse
COPY scenarios/ /muse/scenarios/
COPY studies/ /muse/studies/
# The default `--out out/...` of every command lands here, writable by the muse user; and
# `/archive`, the service's archive folder in deploy/service/compose.yaml.
RUN install -d -o muse -g muse /muse/out /archive

USER 10001:10001
ENTRYPOINT ["muse"]
CMD ["--help"]
