"""The league's peers: adapters like any user's (protocol: ``cross_check.score``), each written
as a careful user of its library would write it and documenting how the library was used, the
event handling per kind and where the library departs from the model.  None imports
``reference``'s or ``fast``'s integration code; each library is imported when the adapter first
runs, so a peer that is not installed costs nothing until it is asked for.

* ``sundials``     -- SUNDIALS CVODE (scikit-sundae), BDF and Adams, root functions;
* ``jaxdiffrax``   -- diffrax (JAX), Tsit5 and Dopri8, ``diffrax.Event``, ``jax.vmap``;
* ``mujoco_slide`` -- MuJoCo 3.x, a slide joint with ``frictionloss`` and a limited range;
* ``shipped``      -- fast, the reference, scipy and heyoka at the league's settings.
"""
