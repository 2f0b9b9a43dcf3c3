/* A small job system for bench_hgcd --tasks: the shape of an engine's own
 * scheduler handed to hgcd through hgcd_world_desc.enqueue_task. `workers - 1`
 * POSIX threads and the thread that calls finish_task take ranges of a loop
 * from one queue (the caller is worker 0); a loop is cut into 4 ranges a
 * worker, or min_range items if that is more. Idle threads sleep on a
 * condition variable. One loop at a time (hgcd finishes each before the
 * next). The threads end with the process. */
#ifndef HGCD_BENCH_JOBS_H
#define HGCD_BENCH_JOBS_H

#include <hgcd/hgcd.h>

#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>

enum { JOBS_MAX_WORKERS = 64, JOBS_MAX_RANGES = 4 * JOBS_MAX_WORKERS };

typedef struct jobs {
    pthread_mutex_t mutex;
    pthread_cond_t work, done;
    hgcd_task_fn *task;
    void *context;
    uint32_t begin[JOBS_MAX_RANGES], end[JOBS_MAX_RANGES];
    int head, tail, remaining, stop;
    unsigned workers;
    pthread_t thread[JOBS_MAX_WORKERS];
    struct jobs_arg {
        struct jobs *j;
        unsigned index;
    } arg[JOBS_MAX_WORKERS];
} jobs;

/* Takes ranges while the queue has some; the mutex is held on entry and exit. */
static void jobs_drain(jobs *j, unsigned worker) {
    while (j->head < j->tail) {
        const int r = j->head++;
        pthread_mutex_unlock(&j->mutex);
        j->task(j->begin[r], j->end[r], worker, j->context);
        pthread_mutex_lock(&j->mutex);
        if (--j->remaining == 0) pthread_cond_broadcast(&j->done);
    }
}

static void *jobs_main(void *p) {
    struct jobs_arg *a = p;
    jobs *j = a->j;
    pthread_mutex_lock(&j->mutex);
    while (!j->stop) {
        jobs_drain(j, a->index);
        if (!j->stop) pthread_cond_wait(&j->work, &j->mutex);
    }
    pthread_mutex_unlock(&j->mutex);
    return NULL;
}

static void *jobs_enqueue(hgcd_task_fn *task, uint32_t count, uint32_t min_range, void *task_context, void *user) {
    jobs *j = user;
    uint32_t range = (count + 4 * j->workers - 1) / (4 * j->workers);
    if (range < min_range) range = min_range;
    pthread_mutex_lock(&j->mutex);
    j->task = task;
    j->context = task_context;
    j->head = j->tail = 0;
    for (uint32_t b = 0; b < count; b += range) {
        j->begin[j->tail] = b;
        j->end[j->tail++] = count - b > range ? b + range : count;
    }
    j->remaining = j->tail;
    pthread_cond_broadcast(&j->work);
    pthread_mutex_unlock(&j->mutex);
    return j;
}

static void jobs_finish(void *handle, void *user) {
    jobs *j = user;
    (void)handle;
    pthread_mutex_lock(&j->mutex);
    jobs_drain(j, 0);
    while (j->remaining > 0) pthread_cond_wait(&j->done, &j->mutex);
    pthread_mutex_unlock(&j->mutex);
}

/* 0 on success. */
static int jobs_start(jobs *j, unsigned workers) {
    if (workers < 1 || workers > JOBS_MAX_WORKERS) return -1;
    j->workers = workers;
    j->head = j->tail = j->remaining = j->stop = 0;
    pthread_mutex_init(&j->mutex, NULL);
    pthread_cond_init(&j->work, NULL);
    pthread_cond_init(&j->done, NULL);
    for (unsigned w = 1; w < workers; ++w) {
        j->arg[w].j = j;
        j->arg[w].index = w;
        if (pthread_create(&j->thread[w], NULL, jobs_main, &j->arg[w])) return -1;
    }
    return 0;
}

#endif
