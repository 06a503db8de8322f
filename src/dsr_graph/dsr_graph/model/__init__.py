"""The graph model (paper, Section II-A): nodes, symbolic and RT edges, the RT tree and its
kinematic chains, rigid transforms, typed values, the vocabulary, transactions with
preconditions, claims. Pure: no ROS import."""
