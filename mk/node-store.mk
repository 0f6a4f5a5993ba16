# Node-store design study: hit rates of a preloaded top of the tree
# (image order and breadth-first) and of an LRU cache, per store size, on the
# regression scenes -> build/node-store/study.md (quoted in docs/node-store.md).
.PHONY: node-store-study
node-store-study: setup ## Node-store hit rates (preload vs cache) per store size
	$(SBT) "runMain rtaccel.study.NodeStoreStudy $(or $(MAX_RAYS),2048)"
