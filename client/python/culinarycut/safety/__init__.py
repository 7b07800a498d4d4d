"""The data side of the manipulation safety module: a sweep of prescribed knife cuts through the MPM
engine (cc-cut) recording the peak blade force against knife speed and material (`dataset`), a
posynomial force model fitted to it (`posynomial`, `fit`), the asset the server's limiter reads
(`asset`) and the safe speed under a force limit (`speed_limit`)."""
