"""The CulinaryCut paper's Cutting Style Transfer Module (CSTM): a learned policy's normal-style actions turned
into another cutting style while the knife is in the food.

    contact_classifier.py   C(I): a ViT (torchvision's, from scratch) saying knife-food contact from a camera image
    contact_data.py         C's training frames and labels: a robomimic export's images and obs/knife_contact
    classifier_train.py     C's training loop (seeded, checkpointed, resumable; held-out accuracy)
    trajectories.py         a recorded cut in the policy's action units, its contact segments, resampling
    pairs.py                (normal, style) contact segments of one scene -> the generator's training windows
    oracle_pairs.py         such pairs recorded through a live server with the scripted oracle, saved and loaded
    style_generator.py      f(a_hat chunk, style): a small transformer with a learned style embedding
    generator_train.py      f's training loop (behaviour cloning on the pairs)
    policy.py               CstmPolicy: any runner policy wrapped; a^s = f(a_hat, style) while C(I_t) = 1, else a_hat
    cli.py                  `python -m culinarycut_learning cstm-classifier train` / `cstm-generator pairs|train`

docs/learning.md ("CSTM") says what each part does and what is not done yet."""
