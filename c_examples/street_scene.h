/* street_scene.h: the street of Grillon & Thalmann's second example, generated the same way
 * everywhere (a small xorshift generator): characters walking up and down a 120 m x 14 m
 * street along Z (Y up), standing, or sitting on benches at its sides, and scene objects
 * (windows, lamps) along both sides. Shared by street.c and models.c. */
#ifndef STREET_SCENE_H
#define STREET_SCENE_H

#include <stdio.h>
#include <stdlib.h>

#include "crowdgaze.h"

#define STREET_LENGTH 120.0f
#define STREET_WIDTH 14.0f

typedef struct {
    float x, z, vx, vz; /* ground position and velocity, metres: z along the street */
    int walking;
    int sitting;
} street_person;

typedef struct {
    uint32_t rng;
    int count;
    street_person *people;
    cg_entity_state *states;
    uint32_t *ids;
} street_scene;

static float street_uniform(street_scene *scene, float low, float high) {
    scene->rng ^= scene->rng << 13;
    scene->rng ^= scene->rng >> 17;
    scene->rng ^= scene->rng << 5;
    return low + (high - low) * (float)(scene->rng >> 8) / 16777216.0f;
}

static void street_check(cg_status status, const char *what) {
    if (status != CG_STATUS_OK) {
        char message[256];
        cg_last_error_message(message, sizeof message);
        fprintf(stderr, "%s failed: %s (%s)\n", what, cg_status_str(status), message);
        exit(1);
    }
}

/* Adds `objects` objects and `characters` characters with the given attention model. The
 * arrays are the caller's, each of `characters` elements. */
static void street_populate(street_scene *scene, cg_crowd *crowd, int characters, int objects,
                            uint32_t attention_model) {
    int i;
    scene->rng = 2009u;
    scene->count = characters;
    for (i = 0; i < objects; i++) {
        cg_object_desc object;
        uint32_t id;
        int left = i % 2 == 0;
        object.struct_size = sizeof object;
        street_check(cg_object_desc_init(&object), "cg_object_desc_init");
        object.position.z =
            (float)(i / 2) * STREET_LENGTH / (float)(objects / 2 + 1) + street_uniform(scene, 0.0f, 2.0f);
        object.position.x = left ? 0.3f : STREET_WIDTH - 0.3f;
        object.heading = left ? 1.5708f : -1.5708f; /* facing the street */
        object.look_at_height = (i % 4 == 2) ? 3.5f : 1.5f; /* lamps, windows */
        object.impact = street_uniform(scene, 0.3f, 1.0f);
        street_check(cg_crowd_add_object(crowd, &object, &id), "cg_crowd_add_object");
    }
    for (i = 0; i < characters; i++) {
        cg_character_desc desc;
        float roll = street_uniform(scene, 0.0f, 1.0f);
        street_person *p = &scene->people[i];
        p->z = street_uniform(scene, 0.0f, STREET_LENGTH);
        p->x = street_uniform(scene, 1.5f, STREET_WIDTH - 1.5f);
        p->vx = 0.0f;
        p->vz = 0.0f;
        p->walking = roll < 0.75f;
        p->sitting = roll >= 0.9f;
        desc.struct_size = sizeof desc;
        street_check(cg_character_desc_init(&desc), "cg_character_desc_init");
        scene->states[i].struct_size = sizeof scene->states[i];
        street_check(cg_entity_state_init(&scene->states[i]), "cg_entity_state_init");
        desc.attention_model = attention_model;
        if (p->walking) {
            p->vz = (street_uniform(scene, 0.0f, 1.0f) < 0.5f ? -1.0f : 1.0f) *
                    street_uniform(scene, 0.9f, 1.6f);
            p->vx = street_uniform(scene, -0.1f, 0.1f);
            scene->states[i].flags = CG_STATE_HEADING_FROM_MOTION;
        } else if (!p->sitting) {
            desc.heading = street_uniform(scene, -3.14159f, 3.14159f);
        } else {
            p->x = roll < 0.95f ? 1.0f : STREET_WIDTH - 1.0f;
            desc.heading = p->x < 2.0f ? 1.5708f : -1.5708f;
        }
        desc.position.x = p->x;
        desc.position.z = p->z;
        street_check(cg_crowd_add_character(crowd, &desc, &scene->ids[i]), "add character");
        scene->states[i].id = scene->ids[i];
        scene->states[i].heading = desc.heading;
    }
}

/* Moves the walkers by dt (they turn back at the street's ends) and pushes the frame. */
static void street_advance(street_scene *scene, cg_crowd *crowd, double t, float dt) {
    int i;
    for (i = 0; i < scene->count; i++) {
        street_person *p = &scene->people[i];
        if (p->walking) {
            p->x += p->vx * dt;
            p->z += p->vz * dt;
            if (p->z < 0.0f || p->z > STREET_LENGTH) p->vz = -p->vz;
            if (p->x < 1.0f || p->x > STREET_WIDTH - 1.0f) p->vx = -p->vx;
        }
        scene->states[i].position.x = p->x;
        scene->states[i].position.z = p->z;
    }
    street_check(cg_crowd_push_frame(crowd, t, scene->states, (size_t)scene->count), "push");
}

#endif /* STREET_SCENE_H */
